"""Structures of the detected marking map: straight markings (Hough lines) and ellipses (images of pitch circles).

They describe the detection, not a camera; the weight-free re-initialisation puts pitch lines and
circles on them. Pixel sizes are at ``line_work_width_px`` (960 px) so they do not change with
the frame size. No I/O.
"""

from __future__ import annotations

import functools
import itertools
import math
from dataclasses import dataclass

import cv2
import numpy as np

from broadtrack_graph.geometry.mask_blobs import blobs_with_stats


@dataclass(frozen=True)
class HatchRule:
    """What makes lines a hatch (:func:`hatched`), not markings: ``min_lines`` parallel lines side by side, within
    ``angle_deg`` of each other and their centres within ``spacing_per_width`` of the width across."""

    min_lines: int = 4
    angle_deg: float = 4.0
    spacing_per_width: float = 0.03


@dataclass(frozen=True)
class MarkingStructureConfig:
    """Settings of :func:`marking_lines` and :func:`marking_ellipses` (pixels at ``line_work_width_px``)."""

    line_work_width_px: int = 960  # the map is reduced to at most this width to find lines and ellipses
    # Straight markings (marking_lines).
    max_lines: int = 12  # at most this many straight markings, strongest first
    # Lines taken from the map before a hatch's are dropped (0: max_lines, no hatch dropped): a goal net's strands or
    # a board's pattern, many lines side by side, would otherwise crowd the pitch lines out of the max_lines kept.
    candidate_lines: int = 0
    hatch: HatchRule = HatchRule()  # the lines of a hatch (a goal net's strands), not markings
    line_min_support_px: float = 30.0  # a straight marking has at least this many map pixels
    line_band_px: float = 1.5  # map pixels this close to a line belong to it
    line_max_gap_px: float = 6.0  # a line's pixels split into runs at gaps longer than this ...
    line_min_run_px: float = 10.0  # ... and runs with fewer pixels are specks, not part of it
    # Ellipses (marking_ellipses).
    max_ellipses: int = 2  # at most this many (0: none looked for)
    ellipse_max_pieces: int = 20  # the largest connected map pieces, fitted in pairs ...
    ellipse_min_piece_px: float = 12.0  # ... of at least this many pixels
    ellipse_check_pixels: int = 1200  # support is counted on at most about this many map pixels
    ellipse_band_px: float = 1.5  # map pixels this close to an ellipse support it ...
    ellipse_min_support_px: float = 80.0  # ... and an ellipse needs this many
    ellipse_max_ratio: float = 0.8  # minor / major axis at most (a ground circle seen from a broadcast camera) ...
    ellipse_min_ratio: float = 0.06  # ... and at least (flatter: a straight marking or the board bases, not a circle)
    ellipse_min_coverage: float = 0.4  # map pixels on it per pixel of its outline inside the image (a painted
    #                                    circle is drawn all along, players aside; chance fits through pieces are not)
    ellipse_min_inside: float = 0.6  # share of its outline inside the image; fewer: an arc at the border (its axes
    #                                  are poorly determined: asked for separately, see marking_ellipses)
    ellipse_max_tilt_deg: float = 30.0  # major axis within this of the image horizontal (roll about 0)
    # The pieces are cut where the straight markings with at least this many map pixels cross them (0: not cut): an
    # arc meeting its line (a penalty arc and its 16.5 m line) would otherwise be one piece with it, and no ellipse fits
    ellipse_cut_line_px: float = 0.0
    ellipse_cut_band_px: float = 2.0  # ... map pixels this close to such a line are cut off


@dataclass(frozen=True)
class ImageLine:
    """A straight marking found in the marking map, in frame pixels.

    normal: (2,) unit normal n; points p on the line satisfy n . p + offset_px = 0.
    centre_px: (2,) middle of its support; direction: (2,) unit, along the line.
    extent_px: (lo, hi) 10th and 90th percentiles of its support along ``direction`` from ``centre_px``.
    support_px: number of map pixels on it, in frame pixels (about its visible length).
    """

    normal: np.ndarray
    offset_px: float
    centre_px: np.ndarray
    direction: np.ndarray
    extent_px: tuple[float, float]
    support_px: float

    def ends_px(self) -> np.ndarray:
        """(2, 2) the ends of its support (``extent_px`` along ``direction`` from ``centre_px``), frame pixels, in the
        dtype of ``centre_px`` and ``direction``."""
        return np.array([self.centre_px + e * self.direction for e in self.extent_px])


def _at_most_width(marking_mask: np.ndarray, width_px: int) -> np.ndarray:
    """The bool map reduced (area-averaged, any marked pixel kept) to at most width_px wide."""
    h, w = marking_mask.shape
    if w <= width_px:
        return marking_mask
    h_new = max(1, int(round(h * width_px / w)))
    return cv2.resize(marking_mask.astype(np.uint8) * 255, (width_px, h_new), interpolation=cv2.INTER_AREA) > 0


def marking_lines(marking_mask: np.ndarray, frame_width_px: int,
                  config: MarkingStructureConfig = MarkingStructureConfig()) -> list[ImageLine]:
    """Straight markings of the map by a greedy Hough transform: take the strongest line, remove its pixels, repeat.

    Removing each line's pixels before looking for the next keeps one long marking from
    returning as many near-copies and lets short dashed lines through after long ones.

    Args:
        marking_mask: (h, w) bool map (any size of the frame's aspect ratio).
        frame_width_px: the frame width the lines are returned in.

    With ``candidate_lines`` above ``max_lines``, that many lines are taken, the lines of a hatch
    (:func:`hatched`) dropped, and the ``max_lines`` best supported of the others returned.

    Returns:
        Up to ``max_lines`` lines, strongest first.
    """
    marking_mask = _at_most_width(marking_mask, config.line_work_width_px)
    h, w = marking_mask.shape
    unit = w / 960.0
    min_support = max(10.0, config.line_min_support_px * unit)
    xs, ys = _nonzero_xy(marking_mask)
    if len(xs) < min_support:
        return []
    pix = np.column_stack([xs, ys]).astype(np.float32) - np.float32([w / 2.0, h / 2.0])
    theta_bins = 180
    thetas = np.arange(theta_bins) * (math.pi / theta_bins)
    cs, sn = np.cos(thetas).astype(np.float32), np.sin(thetas).astype(np.float32)
    r_max = int(math.ceil(math.hypot(w, h) / 2)) + 2
    n_r = 2 * r_max + 1
    # Each (theta, rho) bin's index in the flat accumulator, less the pixel's rounded rho: whole numbers under 2^24,
    # exact in float32.
    bin_shift = (n_r * np.arange(theta_bins) + r_max).astype(np.float32)

    def votes(points):
        # (M, 180) rho of each pixel at each theta (float32), rounded and moved to its bin: the pixels' votes.
        r = points[:, :1] * cs
        r += points[:, 1:] * sn
        np.rint(r, out=r)
        r += bin_shift
        return np.bincount(r.astype(np.intp).ravel(), minlength=n_r * theta_bins)

    def spread(counts, into, combine):
        # A 3-bin window across rho combined into ``into`` (np.add or np.subtract): lines a pixel off the bin centre
        # still collect all votes (rho never reaches the ends of its theta's bins: no vote spills into the next's).
        counts = counts.astype(np.int32)
        combine(into, counts, out=into)
        combine(into[1:], counts[:-1], out=into[1:])
        combine(into[:-1], counts[1:], out=into[:-1])

    acc = np.zeros(n_r * theta_bins, np.int32)  # the pixels no line has taken yet (pix, in their order)
    spread(votes(pix), acc, np.add)
    band = config.line_band_px * unit
    scale = frame_width_px / w
    lines: list[ImageLine] = []
    pool = max(config.max_lines, config.candidate_lines)
    for _ in range(3 * pool):
        k = int(np.argmax(acc))
        if acc[k] < min_support:
            break
        t_i, r_i = divmod(k, n_r)
        normal = np.array([cs[t_i], sn[t_i]], float)
        near = np.abs(pix @ normal - (r_i - r_max)) < 2.0 * unit
        centre = pix[near].mean(axis=0) if near.any() else normal * (r_i - r_max)
        for _refit in range(2):  # total least squares on the band, twice
            sel = pix[near]
            if len(sel) < 5:
                break
            centre = sel.mean(axis=0)
            _, _, vt = np.linalg.svd(sel - centre, full_matrices=False)
            normal = vt[1]
            near = near | (np.abs((pix - centre) @ normal) < band)
        taken, pix = pix[near], pix[~near]
        spread(votes(taken), acc, np.subtract)
        direction = np.array([-normal[1], normal[0]])
        # Pieces of the line: runs of pixels along it without gaps; specks (short runs) do not count.
        along = np.sort((taken - centre) @ direction)
        breaks = np.nonzero(np.diff(along) > config.line_max_gap_px * unit)[0] + 1
        runs = [run for run in np.split(along, breaks) if len(run) >= config.line_min_run_px * unit]
        support = sum(len(run) for run in runs)
        if support < min_support:
            continue
        kept = np.concatenate(runs)  # sorted, as along is
        lo, hi = _sorted_percentile(kept, 0.1), _sorted_percentile(kept, 0.9)  # stray runs at the ends do not count
        centre_px = (centre + [w / 2.0, h / 2.0]) * scale
        lines.append(ImageLine(normal, float(-normal @ centre_px), centre_px, direction,
                               (float(lo * scale), float(hi * scale)), float(support * scale)))
        if len(lines) >= pool:
            break
    if pool > config.max_lines and lines:
        crowded = hatched(lines, frame_width_px, config.hatch)
        kept = [line for line, out in zip(lines, crowded) if not out]
        lines = sorted(kept, key=lambda line: -line.support_px)[:config.max_lines]
    return lines


def _nonzero_xy(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(xs, ys) (N,) int32 of a bool map's set pixels in row order: ``np.nonzero``'s pixels (swapped), read by
    OpenCV."""
    found = cv2.findNonZero(np.ascontiguousarray(mask, dtype=bool).view(np.uint8))
    if found is None:
        return np.zeros(0, np.int32), np.zeros(0, np.int32)
    found = found.reshape(-1, 2)
    return found[:, 0], found[:, 1]


def _sorted_percentile(values: np.ndarray, share: float) -> float:
    """The ``share`` (0-1) quantile of a non-empty sorted float array by linear interpolation: the number
    ``np.percentile(values, 100 * share)`` gives (its steps, without its general machinery: the two neighbours'
    difference in the array's precision, the interpolation in float64)."""
    at = (len(values) - 1) * share
    if at >= len(values) - 1:
        return float(values[-1])
    below = math.floor(at)
    weight = at - below
    a, b = values[below], values[below + 1]
    step = float(b - a)
    return float(b) - step * (1 - weight) if weight >= 0.5 else float(a) + step * weight


def hatched(lines: list[ImageLine], width_px: float, rule: HatchRule = HatchRule()) -> np.ndarray:
    """(L,) bool: the lines of a hatch, with at least ``rule.min_lines - 1`` others within ``rule.angle_deg`` of their
    direction whose centres lie side by side within ``rule.spacing_per_width`` of the width (a goal net, a striped
    kit, a board's pattern), unless twice as long as the hatch's typical line (a marking beside a net, the goal line
    under it). The pitch's parallel markings stand 5.5 m apart or more, and never come three or more so close."""
    directions = np.array([line.direction for line in lines])
    centres = np.array([line.centre_px for line in lines])
    halves = np.array([0.5 * (line.extent_px[1] - line.extent_px[0]) for line in lines])
    parallel = np.abs(directions @ directions.T) > math.cos(math.radians(rule.angle_deg))
    offset = centres[None, :, :] - centres[:, None, :]
    across = np.abs(offset[..., 0] * directions[:, None, 1] - offset[..., 1] * directions[:, None, 0])
    along = np.abs(np.einsum("jki,ji->jk", offset, directions))
    side_by_side = parallel & (across < rule.spacing_per_width * width_px) & (along < halves[:, None] + halves[None, :])
    support = np.array([line.support_px for line in lines])
    typical = np.array([np.median(support[row]) for row in side_by_side])
    # A long marking beside a net (the goal line under it) stands out of the hatch by its length.
    return (side_by_side.sum(axis=1) >= rule.min_lines) & (support < 2.0 * typical)  # itself included


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
    points = np.asarray(points_px, float).reshape(-1, 2)
    # Per ellipse in Python's scalar arithmetic (its cos, sin and squares), each point in numpy's.
    terms = np.array([[centre[0], centre[1], math.cos(angle), math.sin(angle), a, b, a**2, b**2]
                      for centre, (a, b), angle in ellipses], float).reshape(-1, 8, 1)
    cx, cy, c, s, a, b, a2, b2 = terms.transpose(1, 0, 2)  # each (K, 1)
    dx, dy = points[:, 0] - cx, points[:, 1] - cy
    x, y = dx * c + dy * s, -dx * s + dy * c
    return ((x / a) ** 2 + (y / b) ** 2 - 1.0) / np.maximum(2.0 * np.hypot(x / a2, y / b2), 1e-12)


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
    xs, ys = _nonzero_xy(labels > 0)
    pixels = np.column_stack([xs, ys]).astype(np.float32)
    piece_pixels = {}
    for label in pieces:
        own = pixels[labels[ys, xs] == label]
        piece_pixels[label] = own[np.linspace(0, len(own) - 1, min(len(own), 40)).astype(int)]
    if config.ellipse_cut_line_px > 0:  # the support is counted on the whole map, the cut pixels too
        pixels = np.column_stack(_nonzero_xy(marking_mask)).astype(np.float32)
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
        c, s = math.cos(theta), math.sin(theta)
        x = (pixels[:, 0] - cx) * c + (pixels[:, 1] - cy) * s
        y = -(pixels[:, 0] - cx) * s + (pixels[:, 1] - cy) * c
        F = (x / a) ** 2 + (y / b) ** 2 - 1.0
        grad = 2.0 * np.hypot(x / a**2, y / b**2)
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
    marking_mask = _at_most_width(marking_mask, config.line_work_width_px)
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
