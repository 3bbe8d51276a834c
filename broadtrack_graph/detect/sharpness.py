"""How blurred a frame is: the width of its strongest edges against the width a sharp frame's have. No I/O.

A fast pan smears every marking across its motion, a soft lens or a camera of low resolution every edge. The
strongest edges of the frame (the markings, the players, the boards' edges) tell by how much: across each, the
contrast over the steepest gradient is the edge's width (a step edge's central difference spreads it over 2 px;
the strongest edges of sharp broadcast frames measure :data:`SHARP_EDGE_WIDTH_PX` at the working width). A frame
enlarged to the working width (a 640 px video) shows edges wider by the enlargement without being blurred: its
sharp width is scaled by it. A blur along one direction only (a pure pan's) leaves the edges along it sharp, and
they are most of the strongest: such a frame reads as sharp (:mod:`.motion_blur` finds that smear and undoes it
first).
"""

from __future__ import annotations

import cv2
import numpy as np

SHARP_EDGE_WIDTH_PX = 2.2
"""Median width of the strongest edges of a sharp frame at the detector's working width (a perfect step 2.0 with the
3x3 central difference; the lens and the resampling add the rest): 2.1-2.5 px on real 720p and 1080p broadcasts."""


def edge_width_px(grey: np.ndarray, strongest: int = 3000, reach_px: int = 12) -> float | None:
    """Median width (pixels) of the ``strongest`` edges of a grey image: across each (along its gradient,
    ``reach_px`` each way) the contrast over the gradient there. None when the image has too few pixels.

    Args:
        grey: (h, w) uint8 grey image.
    """
    image = grey.astype(np.float32)
    gx, gy = gradients(image)
    magnitude = cv2.magnitude(gx, gy)
    h, w = image.shape
    m = reach_px + 1
    inner = magnitude[m:h - m, m:w - m]
    if inner.size < strongest:
        return None
    rows, cols = _strongest(inner, strongest)
    rows, cols = rows + m, cols + m
    gradient = np.maximum(magnitude[rows, cols], 1e-3)
    nx, ny = gx[rows, cols] / gradient, gy[rows, cols] / gradient
    steps = np.arange(-reach_px, reach_px + 1, dtype=np.float32)
    xs = (cols[:, None] + steps * nx[:, None]).astype(np.float32)
    ys = (rows[:, None] + steps * ny[:, None]).astype(np.float32)
    profile = cv2.remap(image, xs, ys, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    contrast = cv2.reduce(profile, 1, cv2.REDUCE_MAX)[:, 0] - cv2.reduce(profile, 1, cv2.REDUCE_MIN)[:, 0]
    return float(np.median(contrast / gradient))


def gradients(image: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(gx, gy) float32 (h, w): the 3x3 Sobel derivatives of a float32 image (h, w), in grey levels per pixel."""
    return (cv2.Sobel(image, cv2.CV_32F, 1, 0, ksize=3, scale=0.125),
            cv2.Sobel(image, cv2.CV_32F, 0, 1, ksize=3, scale=0.125))


def _strongest(magnitude: np.ndarray, count: int) -> tuple[np.ndarray, np.ndarray]:
    """(rows, cols) of the ``count`` largest pixels of ``magnitude`` (h, w) float32 (ties taken in any order): those
    at least a level that every fourth row and column puts at about twice ``count`` pixels over it, ranked (the
    whole image ranked when fewer pass)."""
    sample = magnitude[::4, ::4].ravel()
    k = 2 * count * len(sample) // magnitude.size
    if 1 <= k < len(sample):
        over = cv2.findNonZero(cv2.compare(magnitude, float(np.partition(sample, -k)[-k]), cv2.CMP_GE))
        if over is not None and len(over) >= count:
            cols, rows = over.reshape(-1, 2).T
            top = np.argpartition(magnitude[rows, cols], -count)[-count:]
            return rows[top], cols[top]
    return np.unravel_index(np.argpartition(magnitude.ravel(), -count)[-count:], magnitude.shape)


def blur_factor(grey: np.ndarray, frame_width_px: int) -> float:
    """How many times wider the strongest edges of the working grey image ``grey`` are than a sharp frame's (1: sharp
    or no edges to tell), a frame ``frame_width_px`` wide enlarged to it taken as sharp at its own pixels' width."""
    width = edge_width_px(grey)
    if width is None:
        return 1.0
    sharp = SHARP_EDGE_WIDTH_PX * max(1.0, grey.shape[1] / float(frame_width_px))
    return max(1.0, width / sharp)
