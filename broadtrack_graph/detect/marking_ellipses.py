"""Ellipses of the detected marking map: the images of the pitch's circles (the centre circle, the penalty arcs),
fitted to the map's connected pieces (:func:`marking_ellipses`), and the first-order distance of points to them.

Settings: :class:`~broadtrack_graph.detect.marking_structures.MarkingStructureConfig` (pixels at its
``line_work_width_px``, 960 px, whatever the frame size). No I/O.
"""

from __future__ import annotations

import functools
import itertools
import math
from dataclasses import dataclass

import cv2
import numpy as np

from broadtrack_graph.detect.marking_structures import ImageLine, MarkingStructureConfig, at_most_width, nonzero_xy
from broadtrack_graph.geometry.mask_blobs import blobs_with_stats


@dataclass(frozen=True)
class ImageEllipse:
    """An ellipse found in the marking map (frame pixels): centre_px (2,), semi-axes (a >= b), angle_rad of a
    to the image x axis, and support_px: map pixels on it (in frame pixels)."""

    centre_px: np.ndarray
    semi_axes_px: tuple[float, float]
    angle_rad: float
    support_px: float

    def distances_px(self, points_px: np.ndarray) -> np.ndarray:
        """(N,) approximate distances (first order) of frame-pixel points (N, 2) to the ellipse."""
        return np.abs(self.signed_distances_px(points_px))

    def signed_distances_px(self, points_px: np.ndarray) -> np.ndarray:
        """(N,) :meth:`distances_px` signed: negative inside the ellipse."""
        return signed_distances_to_ellipses([(self.centre_px, self.semi_axes_px, self.angle_rad)], points_px)[0]

    def outline_px(self, samples: int = 64) -> np.ndarray:
        """(samples, 2) points of the outline, evenly spaced in the parametric angle, frame pixels."""
        t = np.linspace(0.0, 2.0 * math.pi, samples, endpoint=False)
        c, s = math.cos(self.angle_rad), math.sin(self.angle_rad)
        x, y = self.semi_axes_px[0] * np.cos(t), self.semi_axes_px[1] * np.sin(t)
        return np.column_stack([self.centre_px[0] + c * x - s * y, self.centre_px[1] + s * x + c * y])


def signed_distances_to_ellipses(ellipses, points_px: np.ndarray) -> np.ndarray:
    """(K, N) first-order signed distances (negative inside) of points (N, 2) to K ellipses, each a triple (centre
    (2,), semi-axes (a, b), angle of a to the image x axis in radians), frame pixels: ``(q - 1) / |grad q|`` with
    ``q = (x / a)^2 + (y / b)^2`` in the ellipse's own axes. Many ellipses in one pass (a fit's shifted copies)."""
    x, y, a, b, a2, b2 = _in_ellipses_axes(ellipses, np.asarray(points_px, float).reshape(-1, 2), float)
    return ((x / a) ** 2 + (y / b) ** 2 - 1.0) / np.maximum(2.0 * np.hypot(x / a2, y / b2), 1e-12)


def _in_ellipses_axes(ellipses, points: np.ndarray, dtype) -> tuple[np.ndarray, ...]:
    """((K, N) x, (K, N) y, then (K, 1) a, b, a^2, b^2): the points (N, 2) in each ellipse's own axes, in ``dtype``
    (the points'), each ellipse's numbers (cos, sin and squares in Python's arithmetic) taken to it as a Python
    number is."""
    terms = np.array([[centre[0], centre[1], math.cos(angle), math.sin(angle), a, b, a**2, b**2]
                      for centre, (a, b), angle in ellipses], dtype).reshape(-1, 8, 1)
    cx, cy, c, s, a, b, a2, b2 = terms.transpose(1, 0, 2)
    dx, dy = points[:, 0] - cx, points[:, 1] - cy
    return dx * c + dy * s, -dx * s + dy * c, a, b, a2, b2


def marking_ellipses(marking_mask: np.ndarray, frame_width_px: int,
                     config: MarkingStructureConfig = MarkingStructureConfig(), at_border: bool = False,
                     lines: list[ImageLine] = ()) -> list[ImageEllipse]:
    """Ellipses through pieces of the marking map: the image of a pitch circle (centre circle, penalty arcs).

    Connected pieces of the map are fitted in pairs (and the long ones alone) with an ellipse;
    an ellipse is kept when it is wide, about level (roll about 0), not flat, drawn along most
    of its outline in the image, and many map pixels lie on it; the best ``max_ellipses``
    distinct ones are returned, most supported first. By default only ellipses mostly inside
    the image (``ellipse_min_inside``); with ``at_border`` only the others (arcs at the image
    border: a tight zoom's centre circle, or a penalty arc, whose fitted axes are less sure). The pieces are
    cut along the long straight markings of ``lines`` (frame pixels; ``ellipse_cut_line_px``); the support is
    counted on the whole map. :func:`marking_ellipses_both` gives both sets from one fit of the pieces.
    """
    return marking_ellipses_both(marking_mask, frame_width_px, config, lines)[1 if at_border else 0]


def marking_ellipses_both(marking_mask: np.ndarray, frame_width_px: int,
                          config: MarkingStructureConfig = MarkingStructureConfig(), lines: list[ImageLine] = ()
                          ) -> tuple[list[ImageEllipse], list[ImageEllipse]]:
    """(:func:`marking_ellipses`, its ``at_border`` set) from one ellipse fit of each piece and pair of pieces."""
    marking_mask, labels, pieces, areas = map_pieces(marking_mask, frame_width_px, lines, config,
                                                     config.ellipse_min_piece_px)
    h, w = marking_mask.shape
    unit = w / 960.0
    if not pieces:
        return [], []
    xs, ys = nonzero_xy(labels > 0)
    pixels = np.column_stack([xs, ys]).astype(np.float32)
    piece_pixels = {}
    for label in pieces:
        own = pixels[labels[ys, xs] == label]
        piece_pixels[label] = own[np.linspace(0, len(own) - 1, min(len(own), 40)).astype(int)]
    if config.ellipse_cut_line_px > 0:  # the support is counted on the whole map, the cut pixels too
        pixels = np.column_stack(nonzero_xy(marking_mask)).astype(np.float32)
    every = max(1, len(pixels) // config.ellipse_check_pixels)
    pixels = pixels[::every]  # support is counted on at most about ellipse_check_pixels map pixels
    trials = [(a,) for a in pieces if areas[a - 1] >= 60 * unit] + list(itertools.combinations(pieces, 2))
    tol = config.ellipse_band_px * unit
    found: tuple[list, list] = ([], [])  # mostly inside the image, at its border
    for trial in trials:
        sample = np.vstack([piece_pixels[label] for label in trial])
        if len(sample) < 6:
            continue
        (cx, cy), (d1, d2), angle_deg = cv2.fitEllipse(sample)
        a, b = max(d1, d2) / 2.0, min(d1, d2) / 2.0
        if not (np.isfinite(a) and b > 1.0 and 0.03 * w < a < 3.0 * w
                and config.ellipse_min_ratio <= b / a <= config.ellipse_max_ratio):
            continue
        theta = math.radians(angle_deg) + (0.0 if d1 >= d2 else math.pi / 2)
        if abs(math.sin(theta)) > math.sin(math.radians(config.ellipse_max_tilt_deg)):
            continue
        # the map pixels within the band, to first order: |q - 1| < band |grad q| (signed_distances_to_ellipses' q)
        x, y, a_, b_, a2, b2 = _in_ellipses_axes([((cx, cy), (a, b), theta)], pixels, np.float32)
        F = (x / a_) ** 2 + (y / b_) ** 2 - 1.0
        grad = 2.0 * np.hypot(x / a2, y / b2)
        support = int(np.count_nonzero(np.abs(F) < tol * np.maximum(grad, 1e-9))) * every
        inside, outline_px = outline_in_image(cx, cy, a, b, theta, w, h)
        if support < config.ellipse_min_coverage * outline_px:
            continue
        found[int(inside < config.ellipse_min_inside)].append((support, np.array([cx, cy]), (a, b), theta))
    scale = frame_width_px / w
    return _most_supported(found[0], scale, unit, config), _most_supported(found[1], scale, unit, config)


def _most_supported(found: list, scale: float, unit: float, config: MarkingStructureConfig) -> list[ImageEllipse]:
    """The best ``max_ellipses`` distinct ellipses of (support, centre, (a, b), theta) at the map's working size
    (scale: frame / working pixels), most supported first."""
    found = sorted(found, key=lambda item: -item[0])
    out: list[ImageEllipse] = []
    for support, centre, (a, b), theta in found:
        if support < config.ellipse_min_support_px * unit:
            break
        if any(np.linalg.norm(centre * scale - e.centre_px) < 0.1 * a * scale for e in out):
            continue
        out.append(ImageEllipse(centre * scale, (a * scale, b * scale), theta, support * scale))
        if len(out) >= config.max_ellipses:
            break
    return out


def map_pieces(marking_mask: np.ndarray, frame_width_px: int, lines: list[ImageLine], config: MarkingStructureConfig,
               min_piece_px: float) -> tuple[np.ndarray, np.ndarray, list[int], np.ndarray]:
    """The connected pieces of a marking map that curves are fitted to.

    The map is reduced to ``line_work_width_px`` and the long straight markings of ``lines`` (frame pixels, at
    least ``ellipse_cut_line_px`` supported) are drawn out of it ``ellipse_cut_band_px`` wide, so that an arc
    meeting its line is a piece of its own (none cut when ``ellipse_cut_line_px`` is 0).

    Returns:
        (the map at its working width (h, w) bool, the pieces' labels (h, w) int (0: none), the labels of the up to
        ``ellipse_max_pieces`` largest pieces of at least ``min_piece_px`` pixels (at 960 px wide), largest first,
        and every piece's pixel count by label - 1).
    """
    marking_mask = at_most_width(marking_mask, config.line_work_width_px)
    h, w = marking_mask.shape
    unit = w / 960.0
    pieces_map = marking_mask.astype(np.uint8)
    if config.ellipse_cut_line_px > 0:
        to_work = w / frame_width_px
        thickness = max(1, int(round(2 * config.ellipse_cut_band_px * unit)) + 1)
        for line in lines:
            if line.support_px * to_work >= config.ellipse_cut_line_px * unit:
                (x0, y0), (x1, y1) = np.rint(line.ends_px() * to_work).astype(int).tolist()
                cv2.line(pieces_map, (x0, y0), (x1, y1), 0, thickness)
    _, labels, stats, _ = blobs_with_stats(pieces_map)
    areas = stats[1:, cv2.CC_STAT_AREA]
    pieces = [1 + int(k) for k in np.argsort(-areas)[: config.ellipse_max_pieces] if areas[k] >= min_piece_px * unit]
    return marking_mask, labels, pieces, areas


@functools.lru_cache(maxsize=4)
def _unit_circle(samples: int) -> tuple[np.ndarray, np.ndarray]:
    """(cos t, sin t) (samples,) of angles t evenly spaced round the circle from 0 (kept: every ellipse asks)."""
    t = np.linspace(0.0, 2.0 * math.pi, samples, endpoint=False)
    cos_t, sin_t = np.cos(t), np.sin(t)
    cos_t.flags.writeable = sin_t.flags.writeable = False
    return cos_t, sin_t


def outline_in_image(cx: float, cy: float, a: float, b: float, theta: float, w: int, h: int,
                      samples: int = 360) -> tuple[float, float]:
    """(share of the ellipse's outline inside a w x h image, that length in pixels): evenly spaced (in
    angle) outline samples and Ramanujan's perimeter (close enough for the tests they serve)."""
    cos_t, sin_t = _unit_circle(samples)
    c, s = math.cos(theta), math.sin(theta)
    x = cx + a * cos_t * c - b * sin_t * s
    y = cy + a * cos_t * s + b * sin_t * c
    inside = np.count_nonzero((x >= 0) & (x < w) & (y >= 0) & (y < h)) / samples
    perimeter = math.pi * (3.0 * (a + b) - math.sqrt((3.0 * a + b) * (a + 3.0 * b)))
    return inside, inside * perimeter
