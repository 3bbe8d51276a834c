"""Random broadcast cameras for ``bench placements --random``: anywhere a broadcast camera stands, seeing the pitch.

A camera is drawn in two steps (SoccerNet pitch frame, metres, z down):

1. **where it stands**: the focal point uniformly by ground area over the ring around the pitch out to
   :data:`REACH_M` from the centre spot, outside the playing area (``|x| > 52.5`` or ``|y| > 34``: both
   sides, behind both goals, the corners), uniformly :data:`HEIGHT_RANGE_M` high (``z = -height``);
2. **what it sees**: the optical axis through a ground point drawn uniformly on the pitch
   (:func:`~broadtrack_graph.geometry.aim.aim_angles` gives pan and tilt), the horizontal field of
   view log-uniformly in :data:`HFOV_RANGE_DEG` (zoom is a factor), roll uniformly within
   +-:data:`ROLL_MAX_DEG`, and k1 by a broadcast zoom lens's law (:func:`lens_k1`).

The view is redrawn at the same position until at least :data:`MIN_PITCH_SHARE` of the image sees the
pitch (:func:`~broadtrack_graph.synth.motion.pitch_coverage` without a margin); a position where
:data:`VIEW_ATTEMPTS` views all fail is itself redrawn. Positions therefore keep their distribution,
views lean towards the pitch-filling ones. Only the renderer's stands are not respected: a focal point
below a stand's rake sees the pitch as if from a platform cut into it. No I/O here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.geometry.aim import aim_angles
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.synth.motion import hfov_to_focal_px, pitch_coverage

HALF_LENGTH_M, HALF_WIDTH_M = 52.5, 34.0
"""Half the playing area (the pitch's lines)."""

REACH_M = 110.0
"""Farthest a focal point stands from the centre spot, horizontally."""

HEIGHT_RANGE_M = (5.0, 60.0)
"""Height of the focal point above the grass."""

HFOV_RANGE_DEG = (8.0, 70.0)
"""Tightest and widest horizontal field of view."""

ROLL_MAX_DEG = 2.0
"""|roll| <= this."""

K1_WIDE_RANGE = (0.0, 0.09)
"""The lens's k1 at the widest field of view, above its tele value (presets: 0.045-0.1 at 42-62 deg)."""

K1_TELE_RANGE = (-0.01, 0.01)
"""k1 at the tightest field of view (presets: 0.008-0.012): near 0, small negative values allowed."""

MIN_PITCH_SHARE = 0.25
"""Least share of the image on the pitch; the view is redrawn otherwise."""

VIEW_ATTEMPTS = 50
"""Views tried at one position before the position is redrawn."""

LOW_HEIGHT_M = 12.0
"""A camera under this height is "low" (a second grouping, across the stands)."""

STANDS = ("main stand", "far side", "behind a goal", "corner")
"""Where a camera stands, by its focal point (:func:`stand_of`)."""


@dataclass(frozen=True)
class RandomCamera:
    """A drawn camera and how it was drawn.

    camera: the camera (SoccerNet convention) at the requested size.
    aim_w: (3,) the ground point its optical axis goes through, metres.
    hfov_deg: its horizontal field of view.
    pitch_share: share of the image on the pitch.
    views_tried: views drawn before this one was kept (all positions counted).
    """

    camera: Camera
    aim_w: np.ndarray
    hfov_deg: float
    pitch_share: float
    views_tried: int

    @property
    def stand(self) -> str:
        return stand_of(self.camera.position_m)

    @property
    def height_m(self) -> float:
        return -float(self.camera.position_m[2])

    @property
    def low(self) -> bool:
        return self.height_m < LOW_HEIGHT_M


def stand_of(position_w) -> str:
    """Where a focal point stands: main stand (y > 34, |x| <= 52.5), far side (y < -34, |x| <= 52.5),
    behind a goal (|x| > 52.5, |y| <= 34), corner (|x| > 52.5, |y| > 34); "pitch" inside the playing area."""
    x, y = float(position_w[0]), float(position_w[1])
    beyond_goal_line, beyond_touchline = abs(x) > HALF_LENGTH_M, abs(y) > HALF_WIDTH_M
    if beyond_goal_line:
        return "corner" if beyond_touchline else "behind a goal"
    if beyond_touchline:
        return "main stand" if y > 0 else "far side"
    return "pitch"


def lens_k1(hfov_deg: float, wide_k1: float, tele_k1: float) -> float:
    """k1 of a broadcast zoom lens at a field of view: ``tele_k1 + wide_k1 (1 - z)^2`` with z the zoom fraction
    (0 at the widest :data:`HFOV_RANGE_DEG`, 1 at the tightest, on the log of the field of view): the presets'
    lens law (:func:`broadtrack_graph.synth.motion.k1_from_focal`) over this zoom range."""
    lo, hi = HFOV_RANGE_DEG
    zoom = float(np.clip(math.log(hi / hfov_deg) / math.log(hi / lo), 0.0, 1.0))
    return tele_k1 + wide_k1 * (1.0 - zoom) ** 2


def draw_position(rng: np.random.Generator) -> np.ndarray:
    """(3,) a focal point: uniform by area outside the playing area within REACH_M, uniform in height (z down)."""
    while True:
        x, y = rng.uniform(-REACH_M, REACH_M, 2)
        if math.hypot(x, y) <= REACH_M and (abs(x) > HALF_LENGTH_M or abs(y) > HALF_WIDTH_M):
            return np.array([x, y, -rng.uniform(*HEIGHT_RANGE_M)])


def draw_view(rng: np.random.Generator, position_w: np.ndarray, width_px: int,
              height_px: int) -> tuple[Camera, np.ndarray, float]:
    """(camera, aim point (3,), horizontal field of view in degrees) of one view from a focal point."""
    aim_w = np.array([rng.uniform(-HALF_LENGTH_M, HALF_LENGTH_M), rng.uniform(-HALF_WIDTH_M, HALF_WIDTH_M), 0.0])
    lo, hi = (math.log(v) for v in HFOV_RANGE_DEG)
    hfov_deg = math.exp(rng.uniform(lo, hi))
    roll = math.radians(rng.uniform(-ROLL_MAX_DEG, ROLL_MAX_DEG))
    k1 = lens_k1(hfov_deg, rng.uniform(*K1_WIDE_RANGE), rng.uniform(*K1_TELE_RANGE))
    pan, tilt = aim_angles(position_w, aim_w)
    focal_px = float(hfov_to_focal_px(math.radians(hfov_deg), width_px))
    return Camera(focal_px, k1, pan, tilt, roll, np.asarray(position_w, float), width_px, height_px), aim_w, hfov_deg


def draw_random_camera(rng: np.random.Generator, width_px: int, height_px: int) -> RandomCamera:
    """A random broadcast camera seeing at least MIN_PITCH_SHARE of pitch (module docstring)."""
    tried = 0
    while True:
        position = draw_position(rng)
        for _ in range(VIEW_ATTEMPTS):
            camera, aim_w, hfov_deg = draw_view(rng, position, width_px, height_px)
            tried += 1
            share = pitch_coverage(camera, margin_m=0.0)
            if share >= MIN_PITCH_SHARE:
                return RandomCamera(camera, aim_w, hfov_deg, share, tried)
