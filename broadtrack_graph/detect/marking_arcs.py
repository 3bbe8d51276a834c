"""Arcs of the marking map: a penalty arc, or the part of a circle a tight view shows, as an ellipse. No I/O.

The images of the pitch's circles are ellipses. :func:`~broadtrack_graph.detect.marking_ellipses.marking_ellipses`
keeps an ellipse drawn along most of its outline in view; a penalty arc, the part of its circle outside the
penalty area (106 deg of 360), never is, and a frame whose only curved marking is one cannot be placed from
it. Here every piece of the map (cut along the long straight markings, so that an arc meeting its 16.5 m line
is a piece of its own) is fitted alone with an ellipse, by the approximate mean square fit (which keeps the
shape of a partial arc better than the algebraic fit), and kept as an arc when

* it bends: the piece stands at least ``min_sagitta_px`` off its own main direction (a straight piece lies on
  any large enough ellipse),
* it lies on the ellipse (median distance under ``max_median_px``, 90th percentile under ``max_p90_px``),
* it spans at least ``min_span_deg`` of the ellipse (in its parametric angle: a short bend could be any
  ellipse's),
* the ellipse is one a ground circle makes in a broadcast camera (about level, as for whole ellipses; not flatter
  than them, but up to ``max_ratio`` round: a high camera behind a goal looks down on its penalty arc).

What the arc is (a penalty arc, the centre circle) is left to the court model, which pairs each arc with
the lines across it (:mod:`broadtrack_graph.reinit.court_circle`). Pixel sizes are at 960 px wide.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from broadtrack_graph.detect.marking_ellipses import ImageEllipse, map_pieces
from broadtrack_graph.detect.marking_structures import ImageLine, MarkingStructureConfig


@dataclass(frozen=True)
class ArcConfig:
    """Settings of :func:`marking_arcs` (pixels at 960 px wide)."""

    max_arcs: int = 3  # at most this many arcs, the most supported first
    min_piece_px: float = 40.0  # a piece of fewer map pixels is not fitted
    min_sagitta_px: float = 4.0  # the piece's extent across its main direction (a straight piece: its width)
    max_median_px: float = 0.7  # the piece's pixels' median distance to the ellipse ...
    max_p90_px: float = 1.6  # ... and 90th percentile
    min_span_deg: float = 30.0  # the part of the ellipse the piece covers, in its parametric angle
    max_ratio: float = 0.95  # minor / major axis at most (a high camera looking down sees a circle nearly round)


def marking_arcs(marking_mask: np.ndarray, frame_width_px: int, lines: list[ImageLine] = (),
                 structures: MarkingStructureConfig = MarkingStructureConfig(), config: ArcConfig = ArcConfig()
                 ) -> list[ImageEllipse]:
    """Ellipses through single curved pieces of the marking map (module docstring), frame pixels.

    Args:
        marking_mask: (H, W) bool marking map (frame size or reduced, same aspect ratio).
        frame_width_px: the frame's width (the ellipses are returned at it).
        lines: the map's straight markings (frame pixels), cut out of it first.
        structures: the map's working width, the cut, and the ellipse shape limits.

    Returns:
        Up to ``max_arcs`` :class:`ImageEllipse`, most supported first; ``support_px`` is the piece's pixels.
    """
    mask, labels, pieces, _ = map_pieces(marking_mask, frame_width_px, lines, structures, config.min_piece_px)
    w = mask.shape[1]
    unit = w / 960.0
    if not pieces:
        return []
    ys, xs = np.nonzero(labels)
    label_of = labels[ys, xs]
    found = []
    for label in pieces:
        own = label_of == label
        pixels = np.column_stack([xs[own], ys[own]]).astype(np.float32)
        arc = _arc_of(pixels, w, unit, structures, config)
        if arc is not None:
            found.append(arc)
    found.sort(key=lambda item: -item[0])
    scale = frame_width_px / w
    return [ImageEllipse(centre * scale, (a * scale, b * scale), theta, support * scale)
            for support, centre, (a, b), theta in found[: config.max_arcs]]


def _arc_of(pixels: np.ndarray, w: int, unit: float, structures: MarkingStructureConfig, config: ArcConfig):
    """(support, centre (2,), (a, b), theta) of the ellipse through one piece's pixels (N, 2), or None."""
    centred = pixels - pixels.mean(axis=0)
    _, axes = np.linalg.eigh(centred.T @ centred)
    if np.ptp(centred @ axes[:, 0]) < config.min_sagitta_px * unit:  # across the piece's main direction
        return None
    (cx, cy), (d1, d2), angle_deg = cv2.fitEllipseAMS(pixels)
    a, b = max(d1, d2) / 2.0, min(d1, d2) / 2.0
    if not (np.isfinite(a) and np.isfinite(b) and b > 1.0 and 0.03 * w < a < 3.0 * w
            and structures.ellipse_min_ratio <= b / a <= config.max_ratio):
        return None
    theta = math.radians(angle_deg) + (0.0 if d1 >= d2 else math.pi / 2)
    if abs(math.sin(theta)) > math.sin(math.radians(structures.ellipse_max_tilt_deg)):
        return None
    c, s = math.cos(theta), math.sin(theta)
    x = (pixels[:, 0] - cx) * c + (pixels[:, 1] - cy) * s
    y = -(pixels[:, 0] - cx) * s + (pixels[:, 1] - cy) * c
    # First-order distance to the ellipse: |F| / |grad F| with F = (x/a)^2 + (y/b)^2 - 1.
    distance = np.abs((x / a) ** 2 + (y / b) ** 2 - 1.0) / np.maximum(2.0 * np.hypot(x / a**2, y / b**2), 1e-12)
    if np.median(distance) > config.max_median_px * unit or np.percentile(distance, 90) > config.max_p90_px * unit:
        return None
    phase = np.sort(np.arctan2(y / b, x / a))
    gaps = np.diff(np.concatenate([phase, phase[:1] + 2.0 * math.pi]))
    if 2.0 * math.pi - gaps.max() < math.radians(config.min_span_deg):
        return None
    return float(len(pixels)), np.array([cx, cy]), (a, b), theta
