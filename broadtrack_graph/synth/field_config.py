"""Settings of the field-model training samples (:mod:`broadtrack_graph.synth.field_samples`).

One frozen dataclass: what the samples show (camera kinds, negatives, players) and one switch per
domain randomisation. A range switch is a (low, high) pair drawn uniformly per sample, or None
for off; a share switch is the share of samples that get the effect, 0 for off. With a switch off
the renderer's own behaviour (``render_settings``, the textures of the seed) applies;
:meth:`SampleConfig.plain` turns every appearance switch off. No I/O here.
"""

from __future__ import annotations

from dataclasses import dataclass

from broadtrack_graph.synth.field_cameras import FIELD_KIND_NAMES, field_camera_kind
from broadtrack_graph.synth.render import RenderSettings

STRIPE_PATTERNS: tuple[str, ...] = ("none", "length", "width", "checker", "diagonal", "circles")
"""Mowing patterns: none, bands across the length (the usual), along it, a checkerboard, diagonal bands,
rings around the centre spot."""

Range = tuple[float, float]


@dataclass(frozen=True)
class SampleConfig:
    """What the samples show and how their appearance is randomised (units in the field names).

    Hue is in OpenCV units (2 degrees), grey levels on 0..255, pixel sizes at the render size
    unless stated. ``plain()`` gives the same content with every appearance switch off.
    """

    # ---- what the samples show
    camera_kinds: tuple[str, ...] = FIELD_KIND_NAMES  # pitch camera kinds, drawn equally often
    negative_share: float = 0.1  # share of views with no pitch camera (half close-ups, half crowd views)
    mirror_share: float = 0.5  # share of kinds off the halfway line standing at their mirror image x -> -x
    reverse_angle_share: float = 0.0  # share at the point reflection (x, y) -> (-x, -y): labels then look mirrored
    min_pitch_share: float = 0.25  # least image share on the pitch (+3 m); the camera is redrawn otherwise
    roll_max_deg: float = 1.0  # |roll| <= this
    k1_scale_range: Range = (0.5, 1.5)  # factor on the kind's lens law for k1 (k1 stays >= 0)
    player_count_range: tuple[int, int] | None = (0, 30)  # players (the renderer's figures); None: the kind's preset
    player_spread_range_m: Range = (6.0, 26.0)  # typical distance of the players from the aim point
    texture_variants: int = 4  # texture seeds (grass grain, boards, stands); each ~25 MB, built once per process
    mask_stride: int = 4  # line masks at 1 / mask_stride of the image size (which must divide by it)
    render_settings: RenderSettings = RenderSettings()  # the renderer's effects where a switch below is off

    # ---- resolution
    render_height_range_px: tuple[int, int] | None = (360, 1080)  # rendered at a size between, then resized

    # ---- the ground (each on: the marking-free texture, grass and markings shaded per pixel)
    grass_hue_shift_range: Range | None = (-10.0, 14.0)  # + towards blue-green, - towards yellow
    grass_saturation_range: Range | None = (0.5, 1.3)  # factor on the saturation
    grass_value_range: Range | None = (0.6, 1.25)  # factor on the brightness
    stripe_patterns: tuple[str, ...] | None = STRIPE_PATTERNS  # drawn uniformly (STRIPE_PATTERNS)
    stripe_count_range: tuple[int, int] = (6, 24)  # stripes over the pitch's length (width patterns: its width)
    stripe_contrast_range: Range = (0.02, 0.14)  # relative brightness step between stripes
    wear_range: Range | None = (0.0, 0.8)  # worn grass (goal mouths, centre, touchlines) and worn paint, 0..1
    turf_share: float = 0.2  # artificial turf: even grass, lines of other sports in colour
    line_width_range_m: Range | None = (0.08, 0.16)  # painted width of the markings
    line_brightness_range: Range | None = (0.75, 1.05)  # paint colour relative to clean white
    shadow_share: float = 0.35  # a stand's hard shadow edge across the pitch
    shadow_darkness_range: Range = (0.25, 0.6)  # relative darkening in the shadow
    floodlight_range: Range | None = (0.0, 0.3)  # relative brightening under floodlight pools

    # ---- the surroundings
    board_recolour_share: float = 0.5  # boards repainted (hue, saturation, brightness)
    crowd_recolour_share: float = 0.5  # crowd and stands repainted

    # ---- image formation
    exposure_range: Range | None = (0.7, 1.3)  # global gain
    white_balance_range: Range | None = (0.9, 1.1)  # gain of the blue and red channels against green
    gamma_range: Range | None = (0.8, 1.25)  # tone curve exponent
    lens_blur_range_px: Range | None = (0.0, 1.6)  # Gaussian sigma at 1920 px width (the renderer's lens blur)
    sharpen_range: Range | None = (0.0, 1.0)  # broadcast detail enhancement (unsharp amount)
    vignetting_range: Range | None = (0.0, 0.35)  # relative darkening in the corners
    motion_blur_share: float = 0.3  # blur along the image motion of a panning camera
    pan_speed_range_deg_s: Range = (5.0, 45.0)  # angular speed for the motion blur
    noise_sigma_range: Range | None = (0.0, 6.0)  # sensor noise, grey levels (RMS)
    graphics_share: float = 0.7  # broadcast graphics: score bug, logo, ticker, lower third, watermark
    jpeg_share: float = 0.7  # JPEG round trip (low bit-rate artefacts)
    jpeg_quality_range: tuple[int, int] = (8, 90)

    def __post_init__(self) -> None:
        for name in self.camera_kinds:
            field_camera_kind(name)  # raises with the known names
        if not self.camera_kinds and self.negative_share < 1.0:
            raise ValueError("camera_kinds is empty: give at least one kind or negative_share = 1")
        for name in ("negative_share", "mirror_share", "reverse_angle_share", "min_pitch_share", "turf_share",
                     "shadow_share", "board_recolour_share", "crowd_recolour_share", "motion_blur_share",
                     "graphics_share", "jpeg_share"):
            value = getattr(self, name)
            if not 0.0 <= value <= 1.0:
                raise ValueError(f"SampleConfig.{name} must be in [0, 1], got {value}")
        if self.mask_stride < 1 or self.texture_variants < 1:
            raise ValueError("SampleConfig.mask_stride and texture_variants must be >= 1")
        for pattern in self.stripe_patterns or ():
            if pattern not in STRIPE_PATTERNS:
                raise ValueError(f"unknown stripe pattern '{pattern}'; choose from {list(STRIPE_PATTERNS)}")
        if self.render_height_range_px is not None and min(self.render_height_range_px) < 16:
            raise ValueError(f"render_height_range_px must be >= 16, got {self.render_height_range_px}")

    @property
    def shades_ground(self) -> bool:
        """True when a ground switch is on: the markings are then painted per pixel (synth.paint)."""
        return any(v is not None for v in (self.grass_hue_shift_range, self.grass_saturation_range,
                                           self.grass_value_range, self.stripe_patterns, self.wear_range,
                                           self.line_width_range_m, self.line_brightness_range,
                                           self.floodlight_range)) or self.turf_share > 0 or self.shadow_share > 0

    @classmethod
    def plain(cls, **changes) -> "SampleConfig":
        """Every randomisation switch off (:data:`RANGE_SWITCHES`, :data:`SHARE_SWITCHES`): the plain renderer's images.

        The cameras, negatives and the players' positions are still drawn; changes are applied last.
        """
        off = {name: None for name in RANGE_SWITCHES}
        off.update({name: 0.0 for name in SHARE_SWITCHES})
        off.update(changes)
        return cls(**off)


RANGE_SWITCHES: tuple[str, ...] = (
    "player_count_range", "render_height_range_px", "grass_hue_shift_range", "grass_saturation_range",
    "grass_value_range", "stripe_patterns", "wear_range", "line_width_range_m", "line_brightness_range",
    "floodlight_range", "exposure_range", "white_balance_range", "gamma_range", "lens_blur_range_px",
    "sharpen_range", "vignetting_range", "noise_sigma_range")
"""The randomisation switches that a None turns off."""

SHARE_SWITCHES: tuple[str, ...] = (
    "turf_share", "shadow_share", "board_recolour_share", "crowd_recolour_share", "motion_blur_share",
    "graphics_share", "jpeg_share")
"""The randomisation switches that a 0 turns off."""
