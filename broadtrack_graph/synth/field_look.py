"""The drawn appearance of one field-model sample: every randomised value, drawn from a SampleConfig.

Every value is drawn whatever the switches say, in a fixed order, and a switch that is off only
discards its value: turning one switch off or on changes nothing else in the sample. What the look
does to the image is :mod:`broadtrack_graph.synth.randomise`. No I/O here.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from broadtrack_graph.synth.field_config import SampleConfig
from broadtrack_graph.synth.texture import LINE_BGR

DRAWS = 48
"""Uniform numbers drawn per look (fixed, so that the stream after them does not depend on the switches)."""


@dataclass(frozen=True)
class Look:
    """One sample's appearance (units as in SampleConfig; None: the effect is off).

    grass_hsv: (hue shift in OpenCV units, saturation factor, value factor) of the grass.
    stripe_pattern: a STRIPE_PATTERNS name; stripe_width_m, stripe_contrast, stripe_sharpness (edge steepness,
        1 soft .. 12 hard), stripe_angle_rad (diagonal bands), stripe_phase (0..1 of a stripe).
    wear: 0..1 worn grass and paint. turf: artificial turf with coloured lines of other sports.
    line_half_width_m, line_bgr: the markings' half width (metres) and paint colour (BGR, 0..255).
    shadow: (edge normal angle rad, edge offset m along it, darkness 0..1, penumbra m) of a hard shadow.
    floodlight: relative brightening under the floodlight pools.
    board_hsv, crowd_hsv: (hue shift, saturation factor, value factor) of the boards / the stands.
    tone: (exposure, blue gain, red gain, gamma) of the whole image.
    lens_blur_px, sharpen, vignetting: the renderer's optics (lens blur sigma at 1920 px).
    pan_speed_deg_s: camera speed for motion blur. noise_sigma: grey levels RMS.
    graphics: broadcast graphics drawn. jpeg_quality: JPEG round trip quality.
    render_height_px: height rendered at before resizing to the requested size (None: the requested size).
    texture_seed: seed of the textures. detail_seed: seed of the noise fields, turf lines, graphics, floodlights.
    """

    grass_hsv: tuple[float, float, float] | None
    stripe_pattern: str | None
    stripe_width_m: float
    stripe_contrast: float
    stripe_sharpness: float
    stripe_angle_rad: float
    stripe_phase: float
    wear: float
    turf: bool
    line_half_width_m: float
    line_bgr: tuple[float, float, float]
    shadow: tuple[float, float, float, float] | None
    floodlight: float
    board_hsv: tuple[float, float, float] | None
    crowd_hsv: tuple[float, float, float] | None
    tone: tuple[float, float, float, float] | None
    lens_blur_px: float | None
    sharpen: float | None
    vignetting: float | None
    pan_speed_deg_s: float | None
    noise_sigma: float | None
    graphics: bool
    jpeg_quality: int | None
    render_height_px: int | None
    texture_seed: int
    detail_seed: int

    def info(self) -> dict:
        """The look as plain Python values (for a dataset's metadata)."""
        return asdict(self)


class _Draws:
    """Consumes a fixed block of uniform numbers in order; a switch that is off still consumes its numbers."""

    def __init__(self, rng: np.random.Generator) -> None:
        self.values = rng.random(DRAWS)
        self.next_index = 0

    def unit(self) -> float:
        value = float(self.values[self.next_index])
        self.next_index += 1
        return value

    def range(self, bounds) -> float | None:
        u = self.unit()
        return None if bounds is None else float(bounds[0] + u * (bounds[1] - bounds[0]))

    def chance(self, share: float) -> bool:
        return self.unit() < share

    def choice(self, options):
        u = self.unit()
        return None if not options else options[min(int(u * len(options)), len(options) - 1)]


def draw_look(rng: np.random.Generator, config: SampleConfig, centre_w: np.ndarray, pitch_sample: bool) -> Look:
    """The look of one sample.

    Args:
        rng: the sample's appearance stream (:data:`DRAWS` numbers and two seeds are taken from it).
        config: the switches and their ranges.
        centre_w: (3,) ground point at the image centre (metres): where a shadow edge is placed.
        pitch_sample: False for a negative (close-up, crowd): no motion blur then.
    """
    d = _Draws(rng)
    texture_seed = int(rng.integers(config.texture_variants))
    detail_seed = int(rng.integers(1 << 31))
    hue = d.range(config.grass_hue_shift_range)
    sat, val = d.range(config.grass_saturation_range), d.range(config.grass_value_range)
    grass = None if (hue, sat, val) == (None, None, None) else (hue or 0.0, sat or 1.0, val or 1.0)
    pattern = d.choice(config.stripe_patterns)
    count = d.range(config.stripe_count_range)
    width_m = (68.0 if pattern == "width" else 105.0) / max(count, 1.0)
    contrast, sharpness = d.range(config.stripe_contrast_range), d.range((1.0, 12.0))
    angle = math.radians(d.range((20.0, 70.0))) * (1 if d.chance(0.5) else -1)
    phase = d.unit()
    wear = d.range(config.wear_range)
    turf = d.chance(config.turf_share)
    width = d.range(config.line_width_range_m)
    brightness = d.range(config.line_brightness_range)
    tint = np.array([d.range((-0.04, 0.04)), 0.0, d.range((-0.04, 0.04))])
    line_bgr = tuple(float(v) for v in np.clip(LINE_BGR * (brightness or 1.0) * (1.0 + tint), 0, 255))
    shadow_on = d.chance(config.shadow_share)
    normal = d.range((-0.7, 0.7)) + (math.pi / 2 if d.chance(0.7) else 0.0) + (math.pi if d.chance(0.5) else 0.0)
    along = math.cos(normal) * float(centre_w[0]) + math.sin(normal) * float(centre_w[1]) + d.range((-25.0, 25.0))
    shadow = (normal, along, d.range(config.shadow_darkness_range), d.range((0.05, 1.5))) if shadow_on else None
    floodlight = d.range(config.floodlight_range)
    board = (d.range((0, 180)), d.range((0.4, 1.3)), d.range((0.5, 1.3)))
    crowd = (d.range((0, 180)), d.range((0.3, 1.3)), d.range((0.5, 1.2)))
    board_on, crowd_on = d.chance(config.board_recolour_share), d.chance(config.crowd_recolour_share)
    exposure = d.range(config.exposure_range)
    blue, red = d.range(config.white_balance_range), d.range(config.white_balance_range)
    gamma = d.range(config.gamma_range)
    tone = None if (exposure, blue, red, gamma) == (None, None, None, None) else (
        exposure or 1.0, blue or 1.0, red or 1.0, gamma or 1.0)
    lens_blur = d.range(config.lens_blur_range_px)
    sharpen, vignetting = d.range(config.sharpen_range), d.range(config.vignetting_range)
    blur_on = d.chance(config.motion_blur_share) and pitch_sample
    pan_speed = d.range(config.pan_speed_range_deg_s)
    noise = d.range(config.noise_sigma_range)
    graphics = d.chance(config.graphics_share)
    jpeg_on = d.chance(config.jpeg_share)
    quality = int(round(d.range(config.jpeg_quality_range)))
    height = d.range(config.render_height_range_px)
    return Look(
        grass_hsv=grass, stripe_pattern=pattern, stripe_width_m=width_m, stripe_contrast=contrast,
        stripe_sharpness=sharpness, stripe_angle_rad=angle, stripe_phase=phase, wear=wear or 0.0, turf=turf,
        line_half_width_m=0.5 * (width or 0.12), line_bgr=line_bgr, shadow=shadow, floodlight=floodlight or 0.0,
        board_hsv=board if board_on else None, crowd_hsv=crowd if crowd_on else None, tone=tone,
        lens_blur_px=lens_blur, sharpen=sharpen, vignetting=vignetting, pan_speed_deg_s=pan_speed if blur_on else None,
        noise_sigma=noise, graphics=graphics, jpeg_quality=quality if jpeg_on else None,
        render_height_px=None if height is None else int(round(height)), texture_seed=texture_seed,
        detail_seed=detail_seed,
    )
