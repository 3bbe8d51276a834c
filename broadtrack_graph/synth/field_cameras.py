"""Cameras of the field-model training samples: every kind of broadcast camera, drawn at random on its
tripod, and the views with no pitch camera (close-ups, crowd).

Each :class:`FieldCameraKind` names where the tripod stands (the synthetic presets of
:mod:`broadtrack_graph.synth.presets` and the camera kinds of :mod:`broadtrack_graph.reinit.positions`,
with a jitter), the zoom range, where the operator aims, and the preset whose lens laws give k1 and
lambda from the focal length and whose delta places the focal point on the tripod
(``C = T - delta r2 + lambda r3``). A kind off the halfway line also stands at its mirror image
x -> -x (the 16 m camera on the other 16 m line, the camera behind the other goal).

Pitch frame in metres, z down (a camera above the pitch has z < 0); angles in radians unless the
name says degrees; pan 0 looks towards -y. No I/O here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.geometry.aim import aim_angles
from broadtrack_graph.geometry.camera import Camera, rotation_from_angles
from broadtrack_graph.geometry.tripod import Tripod, focal_point
from broadtrack_graph.reinit.positions import CAMERA_KINDS, FAR_MAIN_POSITIONS_W, NEAR_MAIN_POSITIONS_W
from broadtrack_graph.synth.broadcast import close_up_cameras, crowd_cameras
from broadtrack_graph.synth.motion import hfov_to_focal_px, k1_from_focal, lambda_from_focal, pitch_coverage
from broadtrack_graph.synth.presets import PRESETS
from broadtrack_graph.synth.scene import DEFAULT_STADIUM

_KIND_POSITIONS = {kind.name: kind.positions_w for kind in CAMERA_KINDS}


@dataclass(frozen=True)
class FieldCameraKind:
    """One kind of broadcast camera for the training samples (metres, pitch frame, z down; degrees where named).

    name: the kind (a FieldSample's ``kind``).
    lens_preset: the synth preset whose lens laws (k1 and lambda from the focal length, over its zoom range) and
        delta are used.
    tripods_w: tripod points T, one drawn per sample, as the kind stands on the +x side (mirror: x -> -x).
    jitter_m: uniform +- jitter of T per axis.
    hfov_range_deg: narrowest and widest horizontal field of view (drawn log-uniformly).
    aim_x_range_m, aim_y_range_m: where the optical axis meets the ground (drawn uniformly), for the listed side.
    mirrors: the kind also stands at the mirror image x -> -x.
    """

    name: str
    lens_preset: str
    tripods_w: tuple[tuple[float, float, float], ...]
    jitter_m: tuple[float, float, float]
    hfov_range_deg: tuple[float, float]
    aim_x_range_m: tuple[float, float]
    aim_y_range_m: tuple[float, float]
    mirrors: bool


def _preset_kind(name: str, preset: str, extra_tripods=(), jitter_m=(2.0, 2.0, 1.0), hfov_range_deg=None,
                 mirrors: bool = False) -> FieldCameraKind:
    spec = PRESETS[preset]
    tripods = (tuple(spec.tripod_T_w), *(tuple(p) for p in extra_tripods))
    return FieldCameraKind(name, preset, tripods, jitter_m, hfov_range_deg or spec.hfov_range_deg,
                           spec.aim_x_range_m, spec.aim_y_range_m, mirrors)


def _positive_x(positions) -> tuple[tuple[float, float, float], ...]:
    return tuple(tuple(p) for p in positions if p[0] >= 0)


FIELD_CAMERA_KINDS: tuple[FieldCameraKind, ...] = (
    # The main camera on the halfway line, zooming from wide to the tight shots of the "hard" preset.
    _preset_kind("main", "main", jitter_m=(3.0, 4.0, 2.0), hfov_range_deg=(8.0, 42.0)),
    # The main camera of larger stadiums, higher and further back, held wide (tactical views).
    FieldCameraKind("tactical", "wide", tuple(FAR_MAIN_POSITIONS_W) + ((0.0, 62.0, -26.0),), (4.0, 6.0, 3.0),
                    (30.0, 62.0), (-30.0, 30.0), (-10.0, 12.0), False),
    # The main camera held wide on a lens with strong barrel distortion.
    _preset_kind("wide", "wide", jitter_m=(3.0, 4.0, 2.0)),
    # A low gantry at the halfway line (lower-league grounds).
    _preset_kind("low", "low", extra_tripods=NEAR_MAIN_POSITIONS_W, jitter_m=(3.0, 1.5, 1.0)),
    # High in the main stand level with a 16.5 m line.
    _preset_kind("16m", "16m", extra_tripods=_positive_x(_KIND_POSITIONS["high-16m"]), jitter_m=(3.0, 3.0, 1.5),
                 mirrors=True),
    # Low, on the extension of a 16.5 m line, between the boards and the first rows.
    _preset_kind("low-16m", "low-16m", extra_tripods=_positive_x(_KIND_POSITIONS["low-16m"]),
                 jitter_m=(2.0, 1.0, 1.0), mirrors=True),
    # High behind a goal on the pitch's long axis.
    _preset_kind("high-behind", "high-behind", extra_tripods=_KIND_POSITIONS["high-behind"][:1],
                 jitter_m=(3.0, 4.0, 2.0), mirrors=True),
    # High in the stand behind and to the side of a goal, looking into the penalty area.
    FieldCameraKind("high-corner", "16m", _positive_x(_KIND_POSITIONS["high-corner"]), (3.0, 3.0, 2.0),
                    (16.0, 46.0), (10.0, 50.0), (-20.0, 22.0), True),
)
"""Every kind of pitch camera a broadcast shows."""

FIELD_KIND_NAMES: tuple[str, ...] = tuple(kind.name for kind in FIELD_CAMERA_KINDS)
"""The names of :data:`FIELD_CAMERA_KINDS`, in order."""

KIND_CLOSE_UP = "close-up"
KIND_CROWD = "crowd"
NEGATIVE_KINDS = (KIND_CLOSE_UP, KIND_CROWD)
"""Views with no pitch camera (a FieldSample's ``kind`` for negatives)."""


def field_camera_kind(name: str) -> FieldCameraKind:
    """The kind called name; ValueError listing the known names otherwise."""
    for kind in FIELD_CAMERA_KINDS:
        if kind.name == name:
            return kind
    raise ValueError(f"unknown camera kind '{name}'; choose from {list(FIELD_KIND_NAMES)}")


@dataclass(frozen=True)
class DrawnCamera:
    """A drawn pitch camera and how it was drawn.

    camera: the camera at the requested size; tripod: its tripod (T, delta); aim_w: (3,) the ground point
    its optical axis was aimed at (metres); mirrored / reversed: placed at x -> -x / (x, y) -> (-x, -y).
    """

    camera: Camera
    tripod: Tripod
    aim_w: np.ndarray
    mirrored: bool
    reversed: bool


def draw_pitch_camera(kind: FieldCameraKind, rng: np.random.Generator, width_px: int, height_px: int,
                      mirror: bool = False, reverse: bool = False, roll_max_deg: float = 1.0,
                      k1_scale_range: tuple[float, float] = (1.0, 1.0), min_pitch_share: float = 0.25,
                      attempts: int = 30) -> DrawnCamera:
    """A random camera of a kind: tripod, aim point, zoom and roll; redrawn until the pitch fills min_pitch_share.

    Args:
        kind: the camera kind.
        rng: the sample's random stream.
        width_px, height_px: image size of the camera.
        mirror: stand at the kind's mirror image x -> -x (ignored for kinds that do not mirror).
        reverse: stand at the point reflection (x, y) -> (-x, -y) of the position (the far side).
        roll_max_deg: |roll| <= this.
        k1_scale_range: factor on the lens law's k1 (drawn uniformly).
        min_pitch_share: least share of the image on the pitch grown by 3 m (motion.pitch_coverage).
        attempts: draws before the last one is kept whatever it shows.
    """
    spec = PRESETS[kind.lens_preset]
    mirror = mirror and kind.mirrors
    sign = np.array([-1.0 if mirror else 1.0, 1.0, 1.0]) * (np.array([-1.0, -1.0, 1.0]) if reverse else 1.0)
    for _ in range(max(1, attempts)):
        base = np.asarray(kind.tripods_w[int(rng.integers(len(kind.tripods_w)))], float)
        T_w = (base + rng.uniform(-1.0, 1.0, 3) * np.asarray(kind.jitter_m)) * sign
        if not DEFAULT_STADIUM.air_contains(T_w):
            continue
        aim_w = np.array([rng.uniform(*kind.aim_x_range_m), rng.uniform(*kind.aim_y_range_m), 0.0]) * sign
        lo, hi = (math.log(math.radians(v)) for v in kind.hfov_range_deg)
        focal_px = float(hfov_to_focal_px(math.exp(rng.uniform(lo, hi)), width_px))
        pan, tilt = aim_angles(T_w, aim_w)
        roll = math.radians(rng.uniform(-roll_max_deg, roll_max_deg))
        k1 = float(k1_from_focal(spec, focal_px, width_px)) * rng.uniform(*k1_scale_range)
        lambda_m = float(lambda_from_focal(spec, focal_px, width_px))
        tripod = Tripod(tuple(float(v) for v in T_w), float(spec.delta_m))
        C_w = focal_point(rotation_from_angles(pan, tilt, roll), tripod, lambda_m)
        camera = Camera(focal_px, k1, pan, tilt, roll, C_w, width_px, height_px)
        drawn = DrawnCamera(camera, tripod, aim_w, mirror, reverse)
        if pitch_coverage(camera, grid=16) >= min_pitch_share:
            break
    return drawn


def draw_close_up_camera(rng: np.random.Generator, subject_w: np.ndarray, width_px: int, height_px: int) -> Camera:
    """A hand-held close-up of a player (the broadcast scene's close-up camera), zoom and aim varied a little.

    Args:
        subject_w: (3,) the player's foot position, metres.
    """
    camera = close_up_cameras(np.asarray(subject_w, float).reshape(1, 3), width_px, height_px,
                              int(rng.integers(1 << 30)))[0]
    return camera.replace(focal_px=camera.focal_px * rng.uniform(0.75, 1.4),
                          pan_rad=camera.pan_rad + math.radians(rng.uniform(-4.0, 4.0)),
                          tilt_rad=camera.tilt_rad + math.radians(rng.uniform(-4.0, 4.0)))


def draw_crowd_camera(rng: np.random.Generator, width_px: int, height_px: int) -> Camera:
    """A pitch-side camera looking into a stand (the broadcast scene's crowd camera), moved to any side.

    The camera stands 3 m up inside the boards, on the near or far touchline or behind a goal, and
    looks at the stand behind it from 2 deg below to 10 deg above the horizon.
    """
    camera = crowd_cameras(1, width_px, height_px, int(rng.integers(1 << 30)))[0]
    side = int(rng.integers(4))  # near stand, far stand, left stand, right stand
    along = rng.uniform(-40.0, 40.0) if side < 2 else rng.uniform(-22.0, 22.0)
    position = {0: (along, 30.0, -3.0), 1: (along, -30.0, -3.0), 2: (-55.5, along, -3.0), 3: (55.5, along, -3.0)}[side]
    facing = {0: math.pi, 1: 0.0, 2: -math.pi / 2, 3: math.pi / 2}[side]
    return camera.replace(position_m=np.asarray(position, float),
                          pan_rad=facing + (camera.pan_rad - math.pi) + math.radians(rng.uniform(-25.0, 25.0)),
                          tilt_rad=math.radians(rng.uniform(92.0, 100.0)),
                          focal_px=camera.focal_px * rng.uniform(0.8, 1.6))
