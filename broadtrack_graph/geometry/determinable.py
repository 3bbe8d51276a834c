"""Do a frame's markings determine its camera? The rule of ``bench placements --random`` and of the court model.

A camera is fixed by the ground-plane homography, which four line correspondences fix: two lines of each of
the pitch's two directions, or a conic (a circle's image) and a line. So a frame **counts** (is determinable)
when, from its true camera and the pitch template:

* at least two distinct straight ground markings parallel to the touchlines (the x direction: the
  touchlines and the long sides of the boxes) **and** at least two parallel to the goal lines (the y
  direction: the goal lines, the halfway line, the boxes' front lines) each show at least
  :data:`MIN_LINE_PX` pixels of their projected length inside the image and in front of the camera; or
* a pitch circle or arc (the centre circle, a penalty arc) shows at least :data:`MIN_CURVE_SHARE` of its
  length, and at least one straight ground marking (either direction) shows :data:`MIN_LINE_PX` pixels.

"Distinct" counts lines, not classes: the two boxes' long sides on one side of the pitch lie on one line
(``y = 20.16``), which counts once. Only geometry decides: players and broadcast graphics hiding a marking
do not change the rule. The markings are sampled every :data:`STEP_M` metres, projected in one call with
the full distortion; a visible length is the sum of the image steps between consecutive samples that are
both visible.

Given a detected marking map (``explained_by``), only the samples on a detected marking count. Whether the
markings a camera explains fix it (:func:`fixes_camera`) counts their constraints against the camera's
unknowns: a camera laying one line on the only marking in view is not fixed by it, however well it explains
that line. No I/O here.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from functools import lru_cache

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import CIRCLE_CLASSES, LINE_CLASSES, PitchDimensions, PitchTemplate, Segment

MIN_LINE_PX = 60.0
"""Least visible projected length of a straight marking that counts, pixels."""

MIN_CURVE_SHARE = 0.4
"""Least visible share of a circle's or an arc's length that counts."""

MIN_ARC_SHARE = 0.15
"""Least share of a circle's length that constrains a camera as an arc (:func:`fixes_camera`)."""

CAMERA_UNKNOWNS = 7
"""Unknowns of a camera with its principal point at the image centre, lens distortion aside: f, three angles, the
focal point."""

TRIPOD_CAMERA_UNKNOWNS = 4
"""Unknowns of such a camera standing on a known tripod: f and three angles (its focal point known)."""

EXPLAINED_PX = 2.5
"""A sample within this of a detected marking pixel is on it (pixels at 960 px wide, the detector's and the
confidence's working width)."""

STEP_M = 0.25
"""Spacing of the marking samples, metres."""


@dataclass(frozen=True)
class Determinability:
    """What a camera sees of the markings (module docstring).

    determinable: the frame counts.
    x_lines, y_lines: distinct straight markings parallel to the touchlines / to the goal lines seen over
        MIN_LINE_PX pixels.
    curves: the circle classes seen over MIN_CURVE_SHARE of their length.
    visible_px: class name -> visible projected length (pixels) of every ground class; a circle's is its length.
    curve_shares: circle class -> visible share of its length.
    """

    determinable: bool
    x_lines: int
    y_lines: int
    curves: tuple[str, ...]
    visible_px: dict[str, float] = field(default_factory=dict)
    curve_shares: dict[str, float] = field(default_factory=dict)

    @property
    def line_grid(self) -> bool:
        """Two straight markings of each direction: they fix the ground plane's homography on their own, with a
        constraint to spare, without a circle (the rule's first case)."""
        return self.x_lines >= 2 and self.y_lines >= 2


@dataclass(frozen=True)
class _Samples:
    points_w: np.ndarray  # (N, 3) every ground class's samples, class after class
    class_index: np.ndarray  # (N,) index into names
    names: tuple[str, ...]
    family: np.ndarray  # (C,) 0: parallel to x, 1: parallel to y, 2: a circle
    offset: np.ndarray  # (C,) a straight line's offset (y of an x line, x of a y line), cm


@lru_cache(maxsize=4)
def _samples(dimensions: PitchDimensions) -> _Samples:
    pitch = PitchTemplate(dimensions)
    names = tuple(n for n in LINE_CLASSES if pitch.is_on_ground(n))
    samples = pitch.sample_uniform(STEP_M, names)
    family, offset = [], []
    for name in names:
        element = pitch.elements[name]
        if name in CIRCLE_CLASSES:
            family.append(2)
            offset.append(0)
            continue
        assert isinstance(element, Segment)
        start, end = np.asarray(element.start_w), np.asarray(element.end_w)
        along_x = abs(end[0] - start[0]) > abs(end[1] - start[1])
        family.append(0 if along_x else 1)
        offset.append(int(round(100 * (start[1] if along_x else start[0]))))
    index = np.concatenate([np.full(len(samples[n]), i) for i, n in enumerate(names)])
    return _Samples(np.vstack([samples[n] for n in names]), index, names, np.array(family), np.array(offset))


def determinability(camera: Camera, pitch: PitchTemplate | None = None,
                     explained_by: np.ndarray | None = None) -> Determinability:
    """The rule of the module docstring for a camera (any size: its own image is meant).

    Args:
        explained_by: optional (h, w) bool detected marking map of the camera's image (any size of its aspect
            ratio): only the samples within :data:`EXPLAINED_PX` of a marking pixel count.
    """
    s = _samples((pitch or PitchTemplate()).dimensions)
    uv, front = camera.project(s.points_w)
    visible = front & camera.in_image(uv)
    if explained_by is not None:
        visible &= _on_map(uv, explained_by, camera.width_px)
    same_class = s.class_index[1:] == s.class_index[:-1]
    pair_seen = same_class & visible[1:] & visible[:-1]
    step_px = np.linalg.norm(np.where(pair_seen[:, None], uv[1:] - uv[:-1], 0.0), axis=1)
    count = len(s.names)
    length_px = np.bincount(s.class_index[:-1], weights=step_px, minlength=count)
    pairs = np.bincount(s.class_index[:-1], weights=same_class, minlength=count)
    share = np.bincount(s.class_index[:-1], weights=pair_seen, minlength=count) / np.maximum(pairs, 1)
    curves = tuple(n for n, f, v in zip(s.names, s.family, share) if f == 2 and v >= MIN_CURVE_SHARE)
    seen = determinability_of_lengths(dict(zip(s.names, length_px)), curves, pitch)
    return replace(seen, visible_px={n: round(float(v), 1) for n, v in zip(s.names, length_px)},
                   curve_shares={n: round(float(v), 3) for n, f, v in zip(s.names, s.family, share) if f == 2})


def determinability_of_lengths(length_px: dict[str, float], curves: tuple[str, ...],
                               pitch: PitchTemplate | None = None) -> Determinability:
    """The rule of the module docstring from what is seen of each marking, however it was measured (a camera's
    projection, an annotation): ``length_px`` ground class -> the length seen, pixels (straight markings of at least
    :data:`MIN_LINE_PX` count, each pitch line once); ``curves``: the circle classes seen enough to count."""
    s = _samples((pitch or PitchTemplate()).dimensions)
    length = np.array([length_px.get(name, 0.0) for name in s.names])
    lines = (s.family < 2) & (length >= MIN_LINE_PX)
    x_lines = len(set(s.offset[lines & (s.family == 0)].tolist()))
    y_lines = len(set(s.offset[lines & (s.family == 1)].tolist()))
    determinable = (x_lines >= 2 and y_lines >= 2) or (bool(curves) and x_lines + y_lines >= 1)
    return Determinability(determinable, x_lines, y_lines, tuple(curves))


def _on_map(uv_px: np.ndarray, marking_map: np.ndarray, width_px: int) -> np.ndarray:
    """(N,) whether each point (frame pixels; non-finite or outside: False) lies within EXPLAINED_PX of a pixel of
    the map."""
    h, w = marking_map.shape
    scale = w / float(width_px)
    reach = max(1, int(np.ceil(EXPLAINED_PX * w / 960.0)))
    kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * reach + 1, 2 * reach + 1))
    near = cv2.dilate(marking_map.astype(np.uint8), kernel) > 0
    inside = np.all(np.isfinite(uv_px), axis=1)
    cells = np.round(np.where(inside[:, None], uv_px, 0.0) * scale).astype(int)
    cols, rows = np.clip(cells[:, 0], 0, w - 1), np.clip(cells[:, 1], 0, h - 1)
    return inside & near[rows, cols]


def fixes_camera(seen: Determinability, surplus: int = 0, unknowns: int = CAMERA_UNKNOWNS) -> bool:
    """Whether the markings counted in ``seen`` give a camera's unknowns as many constraints (and ``surplus`` more): 2
    for each distinct straight marking, 5 for a circle shown over MIN_CURVE_SHARE of its length (an ellipse), 3 for an
    arc over MIN_ARC_SHARE (its place, size and bend), at least ``unknowns`` (CAMERA_UNKNOWNS; a camera on a known
    tripod: TRIPOD_CAMERA_UNKNOWNS) + ``surplus`` in all, with lines of both directions or a circle among them
    (parallel lines alone leave the camera free to slide along them).

    Two lines of each direction, or a circle and a line, as the rule of the module docstring; three lines of one
    direction and one of the other also fix it; two and one do not (one unknown is left). A camera the markings fix
    exactly (a circle and a line) can be laid on them whichever markings they are; a surplus is what checks it.
    """
    constraints = 2 * (seen.x_lines + seen.y_lines)
    shares = list(seen.curve_shares.values())
    constraints += sum(5 if share >= MIN_CURVE_SHARE else 3 if share >= MIN_ARC_SHARE else 0 for share in shares)
    crossing = (seen.x_lines >= 1 and seen.y_lines >= 1) or any(share >= MIN_ARC_SHARE for share in shares)
    return constraints >= unknowns + surplus and crossing
