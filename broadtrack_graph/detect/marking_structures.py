"""Structures of the detected marking map: straight markings (Hough lines) here, ellipses (images of pitch circles)
in :mod:`.marking_ellipses`, both with the settings of :class:`MarkingStructureConfig`.

They describe the detection, not a camera; the weight-free re-initialisation puts pitch lines and
circles on them. Pixel sizes are at ``line_work_width_px`` (960 px) so they do not change with
the frame size. No I/O.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np


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


def at_most_width(marking_mask: np.ndarray, width_px: int) -> np.ndarray:
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
    marking_mask = at_most_width(marking_mask, config.line_work_width_px)
    h, w = marking_mask.shape
    unit = w / 960.0
    min_support = max(10.0, config.line_min_support_px * unit)
    xs, ys = nonzero_xy(marking_mask)
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


def nonzero_xy(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
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
