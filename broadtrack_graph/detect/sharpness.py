"""How blurred a frame is: the width of its strongest edges against the width a sharp frame's have. No I/O.

A fast pan smears every marking across its motion, a soft lens or a camera of low resolution every edge. The
strongest edges of the frame (the markings, the players, the boards' edges) tell by how much: across each, the
contrast over the steepest gradient is the edge's width (a step edge's central difference spreads it over 2 px;
the strongest edges of sharp broadcast frames measure :data:`SHARP_EDGE_WIDTH_PX` at the working width). A frame
enlarged to the working width (a 640 px video) shows edges wider by the enlargement without being blurred: its
sharp width is scaled by it. A blur along one direction only (a pure pan's) leaves the edges along it sharp, and
they are most of the strongest: such a frame reads as sharp (:mod:`.motion_blur` finds that smear and undoes it
first). The edges may be taken from a region only (the pitch, where the markings are looked for): what lies around it
is not blurred with it (a score graphic drawn sharp over a pan, a stand's crowd whose sharp blocks outnumber the
grass's edges, a stand out of the lens's focus).
"""

from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.detect.image_reads import read_at

SHARP_EDGE_WIDTH_PX = 2.2
"""Median width of the strongest edges of a sharp frame at the detector's working width (a perfect step 2.0 with the
3x3 central difference; the lens and the resampling add the rest): 2.1-2.5 px on real 720p and 1080p broadcasts."""


SOBEL_SCALE = 0.125
"""Grey levels per pixel of one 3x3 Sobel sum: its weights add up to 8 across an edge."""


def edge_width_px(grey: np.ndarray, strongest: int = 3000, reach_px: int = 12,
                  where: np.ndarray | None = None) -> float | None:
    """Median width (pixels) of the ``strongest`` edges of a grey image: across each (along its gradient,
    ``reach_px`` each way) the contrast over the gradient there. None when the image has too few pixels.

    Args:
        grey: (h, w) uint8 grey image.
        where: optional (h, w) bool or uint8 region the edges are taken from (their profiles may reach out of it);
            one of fewer than four times ``strongest`` pixels is not enough to tell, and the whole image is used.
    """
    h, w = grey.shape
    m = reach_px + 1
    if h <= 2 * m or w <= 2 * m or (h - 2 * m) * (w - 2 * m) < strongest:
        return None
    # The derivatives of a uint8 image are whole numbers of eighths: exact in int16, made float32 where needed.
    gx16 = cv2.Sobel(grey, cv2.CV_16S, 1, 0, ksize=3)[m:h - m, m:w - m]
    gy16 = cv2.Sobel(grey, cv2.CV_16S, 0, 1, ksize=3)[m:h - m, m:w - m]
    if where is not None:
        region = np.ascontiguousarray(where[m:h - m, m:w - m], dtype=np.uint8)
        if cv2.countNonZero(region) >= 4 * strongest:  # edges outside it count as flat
            gx16 = cv2.bitwise_and(gx16, gx16, mask=region)
            gy16 = cv2.bitwise_and(gy16, gy16, mask=region)
    rows, cols, gradient = _strongest(gx16, gy16, strongest)
    gx, gy = _eighths(gx16[rows, cols]), _eighths(gy16[rows, cols])
    gradient = np.maximum(gradient, 1e-3)
    nx, ny = gx / gradient, gy / gradient
    steps = np.arange(-reach_px, reach_px + 1, dtype=np.float32)
    xs = (cols[:, None] + m + steps * nx[:, None]).astype(np.float32)
    ys = (rows[:, None] + m + steps * ny[:, None]).astype(np.float32)
    profile = read_at(grey.astype(np.float32), xs, ys)
    contrast = cv2.reduce(profile, 1, cv2.REDUCE_MAX)[:, 0] - cv2.reduce(profile, 1, cv2.REDUCE_MIN)[:, 0]
    return float(np.median(contrast / gradient))


def gradients(image: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(gx, gy) float32 (h, w): the 3x3 Sobel derivatives of a float32 image (h, w), in grey levels per pixel."""
    return (cv2.Sobel(image, cv2.CV_32F, 1, 0, ksize=3, scale=SOBEL_SCALE),
            cv2.Sobel(image, cv2.CV_32F, 0, 1, ksize=3, scale=SOBEL_SCALE))


def _eighths(derivative: np.ndarray) -> np.ndarray:
    """float32: int16 Sobel sums in grey levels per pixel (:data:`SOBEL_SCALE`)."""
    return derivative.astype(np.float32) * np.float32(SOBEL_SCALE)


def _magnitude(gx16: np.ndarray, gy16: np.ndarray) -> np.ndarray:
    """float32: the gradient's length (grey levels per pixel) of int16 Sobel sums of any shape, correctly rounded
    (the sum of squares is a whole number, exact in int32)."""
    gx, gy = gx16.astype(np.int32), gy16.astype(np.int32)
    return np.sqrt((gx * gx + gy * gy).astype(np.float32)) * np.float32(SOBEL_SCALE)


def _strongest(gx16: np.ndarray, gy16: np.ndarray, count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(rows, cols, magnitudes) of the ``count`` pixels of the int16 Sobel sums (h, w) with the longest gradient
    (ties taken in any order): those at least a level that every fourth row and column puts at about twice ``count``
    pixels over it, ranked (the whole image ranked when fewer pass). The gradient's length is taken only where one
    derivative alone reaches the level over sqrt(2), as every pixel at the level's does."""
    sample = _magnitude(gx16[::4, ::4], gy16[::4, ::4]).ravel()
    k = 2 * count * len(sample) // gx16.size
    if 1 <= k < len(sample):
        level = float(np.partition(sample, -k)[-k])
        # A whole number of Sobel sums below the level over sqrt(2): the float's rounding kept clear of.
        reach = int(np.floor(8.0 * level / np.sqrt(2.0))) - 1
        below = cv2.bitwise_and(cv2.inRange(gx16, 1 - reach, reach - 1), cv2.inRange(gy16, 1 - reach, reach - 1))
        near = cv2.findNonZero(cv2.bitwise_not(below))
        if near is None:
            return _ranked(gx16, gy16, count)
        cols, rows = near.reshape(-1, 2).T
        magnitude = _magnitude(gx16[rows, cols], gy16[rows, cols])
        over = magnitude >= level
        if np.count_nonzero(over) >= count:
            rows, cols, magnitude = rows[over], cols[over], magnitude[over]
            top = np.argpartition(magnitude, -count)[-count:]
            return rows[top], cols[top], magnitude[top]
    return _ranked(gx16, gy16, count)


def _ranked(gx16: np.ndarray, gy16: np.ndarray, count: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """:func:`_strongest` by ranking every pixel."""
    magnitude = _magnitude(gx16, gy16)
    rows, cols = np.unravel_index(np.argpartition(magnitude.ravel(), -count)[-count:], magnitude.shape)
    return rows, cols, magnitude[rows, cols]


def blur_factor(grey: np.ndarray, frame_width_px: int, where: np.ndarray | None = None) -> float:
    """How many times wider the strongest edges of the working grey image ``grey`` are than a sharp frame's (1: sharp
    or no edges to tell), a frame ``frame_width_px`` wide enlarged to it taken as sharp at its own pixels' width
    (``where``: the region the edges are taken from, as for :func:`edge_width_px`)."""
    width = edge_width_px(grey, where=where)
    if width is None:
        return 1.0
    sharp = SHARP_EDGE_WIDTH_PX * max(1.0, grey.shape[1] / float(frame_width_px))
    return max(1.0, width / sharp)
