"""Player boxes down to the feet: the legs below a body that the detector's opening removed. No I/O.

The weight-free detector finds a player as a non-grass blob that survives an opening wider than a line
(:meth:`~broadtrack_graph.detect.weightfree.WeightFreeDetector.players`). Legs are thinner than that
opening, and on broadcast video they blend into grass colour at the working size (a white sock beside grass
averages to light green), so the blob's box ends at the knees, and a foot point taken from its bottom lies
metres behind the player on the pitch. :func:`boxes_to_the_feet` moves each box's bottom down its legs.
"""

from __future__ import annotations

import math

import cv2
import numpy as np


def boxes_to_the_feet(boxes: np.ndarray, grey: np.ndarray, grass: np.ndarray, contrast: float = 25.0,
                      max_share: float = 1.0, gap_rows: int = 2) -> np.ndarray:
    """The boxes with each bottom moved down the legs below it.

    Below a box, in its columns, a row holds a leg when one of its pixels is ``contrast`` grey levels lighter
    than the grass around (skin, socks) or is not grass (dark boots and socks); a shadow is darker grass and does
    not count, and a row whose such pixels run on beside the box is a marking crossing under the player. The box
    ends at the first ``gap_rows`` rows without a leg, at most ``max_share`` of its height below it.

    Args:
        boxes: (P, 4) [x0, y0, x1, y1] pixels of the bodies (on ``grey``'s grid).
        grey: (h, w) uint8 grey image.
        grass: (h, w) uint8 grass mask (non-zero: grass colour).
        contrast: grey levels above the grass's median (beside and below the box) that make a leg pixel.

    Returns:
        (P, 4) float boxes, the same but for the bottoms.
    """
    out = np.array(boxes, float).reshape(-1, 4)
    h, w = grey.shape
    for k, (x0, y0, x1, y1) in enumerate(np.round(out).astype(int).tolist()):
        x0, x1 = max(0, x0), min(w, x1)
        top, bottom = min(h, y1), min(h, y1 + int(math.ceil(max_share * (y1 - y0))))
        if bottom - top < gap_rows or x1 <= x0:
            continue
        pad = max(1, (x1 - x0) // 2)
        lo, hi = max(0, x0 - pad), min(w, x1 + pad)
        region, on_grass = grey[top:bottom, lo:hi], grass[top:bottom, lo:hi] > 0
        grass_grey = region[on_grass]
        if len(grass_grey) < 10:
            continue
        # Whole grey levels over a level t are those over floor(t): compared with a whole number, no float image.
        off = (region > math.floor(_median_grey(grass_grey) + contrast)) | ~on_grass
        below = off[:, x0 - lo:x1 - lo]
        legs = below.any(axis=1)
        beside = (x0 - lo) + (hi - x1)  # the columns beside the box, either side
        if beside:  # fewer than half of them off the grass's grey (whole counts: exact)
            legs &= 2 * (off.sum(axis=1) - below.sum(axis=1)) < beside
        out[k, 3] = top + _first_run(~legs, gap_rows)
    return out


def _first_run(flags: np.ndarray, length: int) -> int:
    """The index of the first run of ``length`` True values in the (n,) bool ``flags`` (n >= length), n if none."""
    run = flags[:len(flags) - length + 1]
    for step in range(1, length):
        run = run & flags[step:len(flags) - length + 1 + step]
    first = int(np.argmax(run))
    return first if run[first] else len(flags)


def _median_grey(values: np.ndarray) -> float:
    """np.median of uint8 values (the mean of the two middle ones for an even count), from their histogram: the
    same number at a fraction of the cost on the few hundred pixels of a box."""
    cumulative = np.cumsum(np.bincount(values, minlength=256))
    n = int(cumulative[-1])
    low, high = np.searchsorted(cumulative, [(n - 1) // 2, n // 2], side="right")
    return 0.5 * (float(low) + float(high))


def with_legs(body_mask: np.ndarray, bodies: np.ndarray, feet: np.ndarray, margin_px: int) -> np.ndarray:
    """The player mask (h, w) uint8 with each player's legs added: the box from its body's bottom (``bodies``) down
    to its feet (``feet``, the same boxes from :func:`boxes_to_the_feet`), ``margin_px`` wider on each side and
    below (a stride is wider than the body). Socks, skin and boots are thin light ridges on grass: the confidence
    does not count them as markings, nor the flow as grass."""
    out = body_mask.copy()
    h, w = out.shape
    for (x0, _, x1, y_body), (_, _, _, y_feet) in zip(np.round(bodies).astype(int), np.round(feet).astype(int)):
        if y_feet > y_body:
            cv2.rectangle(out, (max(0, x0 - margin_px), max(0, y_body - margin_px)),
                          (min(w - 1, x1 + margin_px), min(h - 1, y_feet + margin_px)), 255, thickness=cv2.FILLED)
    return out
