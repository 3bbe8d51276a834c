"""Training samples of a learned field model (keypoint and line heatmaps -> camera), from our own renders.

:func:`sample_field` makes one sample, deterministic for (seed, index): a camera kind (every pitch
camera of a broadcast, :mod:`broadtrack_graph.synth.field_cameras`, or a negative: a close-up or a
crowd view), a random camera on that kind's tripod with the pitch in view, random players, the
ray-cast renderer's frame under a randomised look (:mod:`broadtrack_graph.synth.field_look`,
:mod:`broadtrack_graph.synth.randomise`, :mod:`broadtrack_graph.synth.graphics`), and exact labels
from the camera: the 57 keypoints of the No Bells Just Whistles / PnLCalib numbering
(:data:`broadtrack_graph.io.nbjw_keypoints.NBJW_KEYPOINTS_W`, numbers 1-57) and one line mask per
SoccerNet class (:data:`broadtrack_graph.geometry.pitch.LINE_CLASSES`).

Kinds follow a balanced schedule: each block of :data:`SCHEDULE_BLOCK` consecutive indices holds
every kind in proportion to its share (negatives ``negative_share``, the pitch kinds the rest, equally),
in a random order per seed and block. With resolution randomisation the frame is rendered at a
random size of the requested aspect ratio (between the configured heights) and resized to the
requested size; the render camera's principal point is placed so that the resize maps it exactly
onto the returned camera. :func:`render_look` is that rendering for any camera and look (benchmarks render
their own cameras with it). No I/O here (writing datasets is a separate step).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from functools import lru_cache

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import LINE_CLASSES, PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves, finite_runs, usable_samples
from broadtrack_graph.io.nbjw_keypoints import NBJW_KEYPOINTS_W
from broadtrack_graph.synth.drawing import SURFACE_GOAL, SURFACE_GROUND, SURFACE_PLAYER, fixed_point
from broadtrack_graph.synth.field_cameras import (
    KIND_CLOSE_UP,
    KIND_CROWD,
    draw_close_up_camera,
    draw_crowd_camera,
    draw_pitch_camera,
    field_camera_kind,
)
from broadtrack_graph.synth.field_config import SampleConfig
from broadtrack_graph.synth.field_look import Look, draw_look
from broadtrack_graph.synth.graphics import draw_broadcast_graphics
from broadtrack_graph.synth.paint import GroundGrid
from broadtrack_graph.synth.presets import PRESETS
from broadtrack_graph.synth.randomise import GroundShader, jpeg_round_trip, tone_and_noise
from broadtrack_graph.synth.render import Renderer, RenderSettings
from broadtrack_graph.synth.scene import PlayerTrack, simulate_players
from broadtrack_graph.synth.texture import TextureSet, make_textures

FIELD_KEYPOINT_COUNT = 57
"""Keypoints of the NBJW / PnLCalib networks (numbers 1-57; row k of the arrays is number k + 1)."""

FIELD_KEYPOINTS_W = np.array([NBJW_KEYPOINTS_W[number] for number in range(1, FIELD_KEYPOINT_COUNT + 1)], float)
"""(57, 3) the keypoints' world points, metres, SoccerNet pitch frame (z down)."""

SCHEDULE_BLOCK = 40
"""Consecutive indices over which the kinds' shares are met exactly."""

TRAIN_SEED = 1
"""The seed of the field model's training samples."""

VALIDATION_SEED = 2001
"""The seed of the samples its thresholds are chosen on (never trained on)."""

HELD_OUT_SEED = 1001
"""The seed of the samples it is measured on (never trained on, never used to choose anything)."""

SAMPLE_STREAM = 2401
"""Random stream of the samples (numpy SeedSequence entropy [seed, index, SAMPLE_STREAM, ...])."""

FIELD_TEXEL_M = 0.05
"""Ground texel of the samples' textures at every render size (metres)."""

_GROUND_CLASSES = np.array([not name.startswith("Goal") for name in LINE_CLASSES])


@dataclass
class FieldSample:
    """One training sample.

    image_bgr: (H, W, 3) uint8 at the requested size.
    camera: the exact camera at (W, H) (SoccerNet convention), None for a negative.
    kind: the pitch camera kind (field_cameras.FIELD_KIND_NAMES) or "close-up" / "crowd" for a negative.
    keypoints_px: (57, 2) float pixels at (W, H) of the NBJW keypoints 1-57 (row k: number k + 1), pixel
        centres at integer coordinates; NaN behind the camera and for a negative.
    keypoint_visible: (57,) bool: in front of the camera, inside [0, W - 1] x [0, H - 1], and neither
        hidden by a player nor under an opaque broadcast graphic (read from the render's surface labels).
    line_masks: (26, H // mask_stride, W // mask_stride) bool, one plane per LINE_CLASSES class: the
        class's projected centre line drawn 1 cell wide (mask pixel j covers image pixels
        [j * stride, (j + 1) * stride)), kept where the frame shows its surface (a quarter of the cell
        ground for a painted class, any goal-frame pixel for a post or crossbar; players and opaque
        graphics hide it). All False for a negative.
    mask_stride: image pixels per mask pixel.
    players: the players drawn (a one-frame PlayerTrack), None when there were none.
    info: how the sample was drawn (render size, tripod, aim point, the look's values, ...).
    """

    image_bgr: np.ndarray
    camera: Camera | None
    kind: str
    keypoints_px: np.ndarray
    keypoint_visible: np.ndarray
    line_masks: np.ndarray
    mask_stride: int
    players: PlayerTrack | None
    info: dict

    @property
    def is_negative(self) -> bool:
        """True for a view with no pitch camera (close-up, crowd)."""
        return self.camera is None


def sample_field(seed: int, index: int, width_px: int, height_px: int,
                 config: SampleConfig = SampleConfig()) -> FieldSample:
    """One training sample (module docstring); the same arguments always give the same sample.

    Args:
        seed: the dataset's seed (>= 0).
        index: the sample's number in the dataset (>= 0).
        width_px, height_px: the image size; both must divide by ``config.mask_stride``.
        config: content and randomisation switches.

    Raises:
        ValueError: a negative seed or index, or a size below 16 px or not divisible by the mask stride.
    """
    stride = int(config.mask_stride)
    if seed < 0 or index < 0:
        raise ValueError(f"seed and index must be >= 0, got seed {seed}, index {index}")
    if width_px < 16 or height_px < 16 or width_px % stride or height_px % stride:
        raise ValueError(f"image size must be at least 16x16 and divide by mask_stride {stride}, "
                         f"got {width_px}x{height_px}")
    kind = sample_kind(seed, index, config)
    rng = np.random.default_rng([int(seed), int(index), SAMPLE_STREAM])
    camera, players, centre_w, info = _scene(kind, rng, width_px, height_px, config)
    look_rng = np.random.default_rng([int(seed), int(index), SAMPLE_STREAM, 1])
    look = draw_look(look_rng, config, centre_w, camera is not None)
    shown = camera if camera is not None else info.pop("negative_camera")
    rendered = render_look(shown, players, look, config)
    image, labels, hidden, render_camera = rendered.image, rendered.labels, rendered.hidden, rendered.render_camera
    info.update(render_size_px=(render_camera.width_px, render_camera.height_px), look=look.info(),
                player_count=_player_count(players))
    if camera is None:
        no_masks = np.zeros((len(LINE_CLASSES), height_px // stride, width_px // stride), bool)
        return FieldSample(image, None, kind, np.full((FIELD_KEYPOINT_COUNT, 2), np.nan),
                           np.zeros(FIELD_KEYPOINT_COUNT, bool), no_masks, stride, players, info)
    keypoints_px, visible = keypoint_labels(camera, render_camera, labels, hidden)
    masks = line_masks(camera, labels, hidden, stride)
    return FieldSample(image, camera, kind, keypoints_px, visible, masks, stride, players, info)


@dataclass
class LookRender:
    """A camera's frame under a look (:func:`render_look`).

    image: (H, W, 3) BGR uint8 at the camera's size.
    labels: (h, w) uint8 surface labels (drawing.SURFACE_*) at the render size.
    hidden: (h, w) bool pixels under opaque broadcast graphics at the render size, or None (no graphics).
    render_camera: the camera at the render size (:func:`render_camera_for`), whose image resized is ``image``.
    """

    image: np.ndarray
    labels: np.ndarray
    hidden: np.ndarray | None
    render_camera: Camera


def render_look(camera: Camera, players: PlayerTrack | None, look: Look,
                config: SampleConfig = SampleConfig(), frame: int = 0) -> LookRender:
    """One frame of a camera under a drawn look: the samples' rendering, reusable for any camera.

    The frame is rendered at the look's render size (the camera's size when the look has none), with the
    ground shaded per pixel when a ground switch of ``config`` is on, then toned, noised, overlaid with
    broadcast graphics, JPEG round-tripped and resized to the camera's size as the look says.

    Args:
        camera: the camera (any size: the image is returned at its size).
        players: the players to draw (frame 0 of the track), or None.
        look: the appearance (:func:`broadtrack_graph.synth.field_look.draw_look` with the same config).
        config: the switches the look was drawn with (which ground shading, which renderer effects).
        frame: a clip's frame under the same look: frame 0 the look's own noise, each later frame its own draw (a
            sensor's noise is new every frame; the scene, the grass and the graphics are the look's).
    """
    width_px, height_px = camera.width_px, camera.height_px
    render_w, render_h = render_size(width_px, height_px, look.render_height_px)
    render_camera = render_camera_for(camera, render_w, render_h)
    textures, shader = None, None
    if config.shades_ground:
        textures = field_textures(look.texture_seed)
        shader = GroundShader(look, GroundGrid.of(textures))
    elif (render_w, render_h) != (width_px, height_px):  # the texel of the samples at every render size
        textures = field_textures(look.texture_seed, painted=True)
    renderer = Renderer(render_w, render_h, seed=look.texture_seed, settings=_render_settings(config, look),
                        textures=textures)
    rendered = renderer.render(render_camera, players, 0, _previous_camera(render_camera, look),
                               background_shader=shader)
    image, labels = rendered.image, rendered.labels
    if look.tone is not None or look.noise_sigma:
        noise_seed = [look.detail_seed, 6] if frame == 0 else [look.detail_seed, 6, frame]
        image = tone_and_noise(image, look, np.random.default_rng(noise_seed))
    hidden = draw_broadcast_graphics(image, np.random.default_rng([look.detail_seed, 7])) if look.graphics else None
    if look.jpeg_quality is not None:
        image = jpeg_round_trip(image, look.jpeg_quality)
    if (render_w, render_h) != (width_px, height_px):
        shrink = render_w > width_px
        image = cv2.resize(image, (width_px, height_px), interpolation=cv2.INTER_AREA if shrink else cv2.INTER_LINEAR)
    return LookRender(image, labels, hidden, render_camera)


def sample_kind(seed: int, index: int, config: SampleConfig = SampleConfig()) -> str:
    """The kind of sample (seed, index): the balanced schedule of the module docstring."""
    return _schedule(int(seed), int(index) // SCHEDULE_BLOCK, config.camera_kinds, float(config.negative_share))[
        int(index) % SCHEDULE_BLOCK]


@lru_cache(maxsize=64)
def _schedule(seed: int, block: int, kinds: tuple[str, ...], negative_share: float) -> tuple[str, ...]:
    names = list(kinds) + [KIND_CLOSE_UP, KIND_CROWD]
    shares = np.array([(1.0 - negative_share) / max(len(kinds), 1)] * len(kinds) + [negative_share / 2] * 2)
    target = shares / shares.sum() * SCHEDULE_BLOCK
    counts = np.floor(target).astype(int)
    rng = np.random.default_rng([seed, block, SAMPLE_STREAM, 3])
    order = np.lexsort((rng.random(len(names)), -(target - counts)))  # largest remainder, ties at random
    counts[order[:SCHEDULE_BLOCK - counts.sum()]] += 1
    return tuple(rng.permutation(np.repeat(names, counts)).tolist())


def _scene(kind: str, rng: np.random.Generator, width_px: int, height_px: int, config: SampleConfig):
    """(camera or None, players, ground point at the image centre (3,), info) of a sample."""
    mirror, reverse = rng.random() < config.mirror_share, rng.random() < config.reverse_angle_share
    low, high = config.player_count_range or (-1, -1)
    count_u, spread_u, players_seed = rng.random(), rng.random(), int(rng.integers(1 << 31))
    if kind in (KIND_CLOSE_UP, KIND_CROWD):
        centre_w = np.array([rng.uniform(-35.0, 35.0), rng.uniform(-22.0, 22.0), 0.0])
        count = max(6, int(low + count_u * (high - low + 1))) if config.player_count_range else 22
        players = simulate_players(centre_w[None], count, 4.0 + 10.0 * spread_u, players_seed)
        if kind == KIND_CLOSE_UP:
            outfield = np.flatnonzero(players.teams < 2)
            subject = players.positions_w[0, outfield[int(rng.integers(len(outfield)))]]
            shown = draw_close_up_camera(rng, subject, width_px, height_px)
        else:
            shown = draw_crowd_camera(rng, width_px, height_px)
        return None, players, centre_w, {"negative_camera": shown}
    spec = field_camera_kind(kind)
    drawn = draw_pitch_camera(spec, rng, width_px, height_px, mirror, reverse, config.roll_max_deg,
                              config.k1_scale_range, config.min_pitch_share)
    preset = PRESETS[spec.lens_preset]
    if config.player_count_range is None:
        count, spread = preset.player_count, preset.player_spread_m
    else:
        count = min(high, int(low + count_u * (high - low + 1)))
        spread_lo, spread_hi = config.player_spread_range_m
        spread = spread_lo + spread_u * (spread_hi - spread_lo)
    players = simulate_players(drawn.aim_w[None], count, float(spread), players_seed) if count > 0 else None
    info = {"tripod_T_w": drawn.tripod.T_w, "delta_m": drawn.tripod.delta_m, "aim_w": tuple(drawn.aim_w.tolist()),
            "mirrored": drawn.mirrored, "reversed": drawn.reversed}
    return drawn.camera, players, drawn.aim_w, info


def _player_count(players: PlayerTrack | None) -> int:
    return 0 if players is None else int(players.positions_w.shape[1])


def render_size(width_px: int, height_px: int, render_height_px: int | None) -> tuple[int, int]:
    """The size rendered at: the requested aspect ratio exactly, the height nearest render_height_px.

    None: the requested size.
    """
    if render_height_px is None:
        return width_px, height_px
    unit = math.gcd(width_px, height_px)
    aspect_w, aspect_h = width_px // unit, height_px // unit
    scale = max(1, round(render_height_px / aspect_h), math.ceil(16 / aspect_h), math.ceil(16 / aspect_w))
    return aspect_w * scale, aspect_h * scale


def render_camera_for(camera: Camera, render_w: int, render_h: int) -> Camera:
    """The camera at the render size whose image, resized to the camera's size (cv2.resize), is the camera's image.

    cv2.resize maps render pixel u to ``(u + 0.5) s - 0.5`` with ``s = W / render_w``; the principal
    point is placed at ``(c + 0.5) / s - 0.5`` so that projections agree exactly.
    """
    if (render_w, render_h) == (camera.width_px, camera.height_px):
        return camera
    scale = camera.width_px / render_w
    centre = camera.principal_point
    principal = ((centre[0] + 0.5) / scale - 0.5, (centre[1] + 0.5) / scale - 0.5)
    return dataclasses.replace(camera.rescaled(render_w, render_h), principal_point_px=principal)


@lru_cache(maxsize=8)
def field_textures(texture_seed: int, painted: bool = False) -> TextureSet:
    """The textures of a seed at :data:`FIELD_TEXEL_M` (cached; ~25 MB each).

    painted: with the markings and stripes of the texture (False: plain grass, for the ground shader).
    """
    return make_textures(FIELD_TEXEL_M, int(texture_seed), markings=painted, stripes=painted)


def _render_settings(config: SampleConfig, look: Look) -> RenderSettings:
    """The renderer's effects: the config's settings with the randomised ones replaced."""
    changes = {}
    if look.noise_sigma is not None:
        changes["noise_sigma"] = 0.0  # added afterwards (randomise.tone_and_noise)
    for name, value in (("lens_blur_sigma_px", look.lens_blur_px), ("sharpen", look.sharpen),
                        ("vignetting", look.vignetting)):
        if value is not None:
            changes[name] = value
    if config.shadow_share > 0:
        changes["shadow"] = False  # the look's shadow edge instead
    if config.jpeg_share > 0:
        changes["jpeg_quality"] = None  # after the graphics (randomise.jpeg_round_trip)
    if look.tone is not None:
        changes["exposure_drift"] = 0.0
    return dataclasses.replace(config.render_settings, **changes)


def _previous_camera(camera: Camera, look: Look) -> Camera | None:
    """The camera one frame (1 / 25 s) earlier for the renderer's motion blur at the look's speed; None: no blur."""
    if look.pan_speed_deg_s is None:
        return None
    direction = np.random.default_rng([look.detail_seed, 5]).uniform(-0.6, 0.6)  # mostly panning, some tilting
    step = math.radians(look.pan_speed_deg_s) / 25.0
    return camera.replace(pan_rad=camera.pan_rad - step * math.cos(direction),
                          tilt_rad=camera.tilt_rad - step * math.sin(direction))


def keypoint_labels(camera: Camera, render_camera: Camera, labels: np.ndarray, hidden: np.ndarray | None):
    """(57, 2) pixel positions at the camera's size (NaN behind it) and (57,) visibility (see FieldSample).

    Args:
        camera: the sample's camera; render_camera: the same at the render size (labels' size).
        labels: (h, w) surface labels of the render; hidden: (h, w) bool under opaque graphics, or None.
    """
    uv, front = camera.project(FIELD_KEYPOINTS_W)
    with np.errstate(invalid="ignore"):
        visible = front & (uv[:, 0] >= 0) & (uv[:, 0] <= camera.width_px - 1)
        visible &= (uv[:, 1] >= 0) & (uv[:, 1] <= camera.height_px - 1)
    if visible.any():
        uv_r, _ = render_camera.project(FIELD_KEYPOINTS_W[visible])
        cols = np.clip(np.rint(uv_r[:, 0]), 0, labels.shape[1] - 1).astype(int)
        rows = np.clip(np.rint(uv_r[:, 1]), 0, labels.shape[0] - 1).astype(int)
        covered = labels[rows, cols] == SURFACE_PLAYER
        if hidden is not None:
            covered |= hidden[rows, cols]
        visible[visible] = ~covered
    return uv, visible


@lru_cache(maxsize=1)
def _mask_curves() -> TemplateCurves:
    return TemplateCurves(PitchTemplate(), line_step_m=0.5, circle_step_m=0.25)


def line_masks(camera: Camera, labels: np.ndarray, hidden: np.ndarray | None, stride: int) -> np.ndarray:
    """(26, H // stride, W // stride) bool per-class line masks of a camera (see FieldSample.line_masks).

    Args:
        camera: the camera at the image size (W, H).
        labels: (h, w) surface labels of the render (any size of the same aspect ratio).
        hidden: (h, w) bool pixels under opaque graphics, or None.
        stride: image pixels per mask pixel.
    """
    W, H = camera.width_px, camera.height_px
    size = (W // stride, H // stride)
    masks = np.zeros((len(LINE_CLASSES), size[1], size[0]), np.uint8)
    curves = _mask_curves()
    for j, name in enumerate(LINE_CLASSES):
        uv, front = camera.project(curves.samples_w[name])
        ok = usable_samples(uv, front, W, H)
        uv_mask = (uv + 0.5) / stride - 0.5  # the resize convention: pixel centres at integers
        for start, stop in finite_runs(ok):
            cv2.polylines(masks[j], [fixed_point(uv_mask[start:stop]).reshape(-1, 1, 2)], False, 1, 1, cv2.LINE_8, 4)
    shown = np.ones(labels.shape, bool) if hidden is None else ~hidden
    ground = cv2.resize(((labels == SURFACE_GROUND) & shown).astype(np.float32), size, interpolation=cv2.INTER_AREA)
    goal = cv2.resize(((labels == SURFACE_GOAL) & shown).astype(np.float32), size, interpolation=cv2.INTER_AREA)
    out = masks > 0
    out[_GROUND_CLASSES] &= (ground >= 0.25)[None]
    out[~_GROUND_CLASSES] &= (goal > 0)[None]
    return out
