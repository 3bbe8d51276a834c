"""Whether a frame shows a marking where a camera draws it across a motion blur's smear, read on the image itself.

A marking of painted width ``w`` crossing a smear of length ``L`` at an angle is spread into a band as wide as the
smear across it, ``a = L |sin|``, at a share ``w / a`` of its contrast (:mod:`.motion_blur`): a 3 px line under a
20 px smear stands a few grey levels over the grass, under the level the ridge detector's threshold keeps, and the
marking map misses it. Where a camera says the marking lies, the image itself can still be asked: the band's middle
brighter than the grass just beyond each of its edges. Averaged along the marking (``window_px`` of its length), a
painted band stands ``margin`` grey levels over its two sides on average and ``side_margin`` over each (a mown
stripe's edge beside it lowers one side's difference), while grass, a camera off by a few pixels across the band
(its middle on one of the band's edges) or a step of light (a mown stripe, a shadow's edge: brighter on one side
only) does not. :func:`shown_across_smear` gives that answer for a camera's template samples; the confidence asks it
for the markings the smear leaves too little contrast for the map to show
(:mod:`~broadtrack_graph.reinit.confidence`). No I/O.

Pixels are the working image's (x right, y down).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from broadtrack_graph.detect.image_reads import read_at


@dataclass(frozen=True)
class SmearedImage:
    """A smeared frame's marking channel as the smear left it (not deblurred), uint8 or float32 (h, w) at the working
    size, where markings may be (h, w) bool (the field inside its edge, off the players), and the working / frame pixel
    scale."""

    channel: np.ndarray
    allowed: np.ndarray
    scale: float


@dataclass(frozen=True)
class SmearCheckConfig:
    """Settings of :func:`shown_across_smear` (working pixels and grey levels)."""

    side_gap_px: float = 3.0  # the grass compared with lies this far beyond each edge of the band
    window_px: int = 31  # the band and its sides averaged over this much of the marking's length (samples ~1 px apart)
    margin: float = 2.0  # the band's middle this much brighter than its two sides on average (the window's means) ...
    side_margin: float = 1.0  # ... and at least this much brighter than each (a band, not a step of light)


def shown_across_smear(image: SmearedImage, uv_px: np.ndarray, run_index: np.ndarray, normal: np.ndarray,
                       band_px: np.ndarray, config: SmearCheckConfig = SmearCheckConfig()
                       ) -> tuple[np.ndarray, np.ndarray]:
    """Whether the frame shows each sample's marking as its smeared band (module docstring).

    Args:
        image: the frame's smeared marking channel.
        uv_px: (N, 2) samples along markings, about 1 px apart, working pixels.
        run_index: (N,) the run of consecutive samples each belongs to (one marking's piece): the window does not
            reach across runs.
        normal: (N, 2) unit normal of the marking at each sample.
        band_px: (N,) the band's width across the marking (the smear's length across it, at least its paint).

    Returns:
        (checked (N,), shown (N,)): checked where the band's middle and both sides lie where markings may be;
        shown where, besides, the window's middle stands ``margin`` over the sides' means on average and
        ``side_margin`` over each.
    """
    n = len(uv_px)
    if n == 0:
        return np.zeros(0, bool), np.zeros(0, bool)
    offset = (0.5 * np.asarray(band_px, float) + config.side_gap_px)[:, None] * normal
    points = np.concatenate([uv_px, uv_px + offset, uv_px - offset])
    x, y = points[:, 0].astype(np.float32), points[:, 1].astype(np.float32)
    values = read_at(image.channel, x, y).astype(np.float32)
    h, w = image.allowed.shape
    inside = (x >= 0) & (x <= w - 1) & (y >= 0) & (y <= h - 1)
    cols, rows = np.clip(np.round(x).astype(int), 0, w - 1), np.clip(np.round(y).astype(int), 0, h - 1)
    allowed = inside & image.allowed[rows, cols]
    middle, side_a, side_b = values[:n], values[n:2 * n], values[2 * n:]
    checked = allowed[:n] & allowed[n:2 * n] & allowed[2 * n:]
    over_a = _run_means(middle - side_a, run_index, config.window_px)
    over_b = _run_means(middle - side_b, run_index, config.window_px)
    band = (0.5 * (over_a + over_b) >= config.margin) & (np.minimum(over_a, over_b) >= config.side_margin)
    return checked, checked & band


def _run_means(values: np.ndarray, run_index: np.ndarray, window: int) -> np.ndarray:
    """(N,) the mean of ``values`` over the ``window`` samples centred on each, within its run (cut at its ends)."""
    n = len(values)
    starts = np.flatnonzero(np.r_[True, run_index[1:] != run_index[:-1]])
    ends = np.r_[starts[1:], n]
    first = np.repeat(starts, ends - starts)
    last = np.repeat(ends, ends - starts)
    i = np.arange(n)
    lo = np.maximum(i - window // 2, first)
    hi = np.minimum(i + window // 2 + 1, last)
    sums = np.r_[0.0, np.cumsum(values, dtype=float)]
    return (sums[hi] - sums[lo]) / (hi - lo)
