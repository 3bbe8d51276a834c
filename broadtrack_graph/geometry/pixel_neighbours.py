"""The pixels of a grid within a distance of sub-pixel points: each point's neighbourhood, all points at once. No I/O.

Pixel (c, r) sits at integer coordinates (c, r). A point of the unit cell past pixel floor(point) can lie within a
tolerance of only a few offsets from that pixel (:func:`reachable_offsets`, the same for every point); each point's
candidates are those K offsets, and :func:`pixels_within` tells which of them lie strictly within the tolerance and
inside the grid: the pairs a k-d tree query of the grid gives, without building a tree.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np


def pixels_within(points_px: np.ndarray, size: tuple[int, int], tolerance_px: float) -> tuple[np.ndarray, np.ndarray]:
    """The pixels of a (w, h) grid strictly closer than ``tolerance_px`` to each point.

    Args:
        points_px: (N, 2) pixel coordinates (x, y), pixel (c, r) at integer coordinates (c, r).
        size: (w, h) of the grid.
        tolerance_px: the distance (pixels).

    Returns:
        near: (N, K) bool, the pair is within the tolerance and the pixel inside the grid; pixel: (N, K) int,
        flat index ``r * w + c`` of each point's K candidate pixels (meaningless where not ``near``).
        The same pairs as a KD-tree query with ``distance_upper_bound=tolerance_px``, without building a tree.
    """
    w, h = size
    reach = reachable_offsets(float(tolerance_px))
    points_px = np.asarray(points_px, float)
    base = np.floor(points_px).astype(np.int32)  # grid indices (a frame is far under 2^31 pixels)
    # Each axis apart, over the few columns and rows along it (A each): the squared distances across them and
    # whether they lie inside the grid; then taken for each of the K reachable offsets.
    cols, rows = base[:, 0:1] + reach.axis, base[:, 1:2] + reach.axis
    dx, dy = cols - points_px[:, 0:1], rows - points_px[:, 1:2]
    dx *= dx
    dy *= dy
    distance2 = dx[:, reach.x_index]
    distance2 += dy[:, reach.y_index]
    near = distance2 < tolerance_px * tolerance_px
    near &= ((cols >= 0) & (cols < w))[:, reach.x_index]
    near &= ((rows >= 0) & (rows < h))[:, reach.y_index]
    return near, (base[:, 1:2] * w + base[:, 0:1]) + (reach.y * w + reach.x)


@dataclass(frozen=True)
class Offsets:
    """The K pixel offsets from floor(point) a point of the unit cell can be within a tolerance of: (K,) int32 x and
    y, the offsets along one axis (A,) int32, and (K,) each offset's place among them along x and along y."""

    x: np.ndarray
    y: np.ndarray
    axis: np.ndarray
    x_index: np.ndarray
    y_index: np.ndarray


@functools.lru_cache(maxsize=8)
def reachable_offsets(tolerance_px: float) -> Offsets:
    """The offsets a point of the unit cell can be within the tolerance of (the same for every call with this
    tolerance: made once)."""
    reach = int(math.ceil(tolerance_px))
    offsets = np.arange(-reach, reach + 2)
    ox, oy = (o.ravel() for o in np.meshgrid(offsets, offsets))
    gap_x, gap_y = np.maximum(np.maximum(ox - 1, -ox), 0), np.maximum(np.maximum(oy - 1, -oy), 0)
    reachable = gap_x * gap_x + gap_y * gap_y < tolerance_px * tolerance_px
    ox, oy = ox[reachable].astype(np.int32), oy[reachable].astype(np.int32)
    arrays = Offsets(ox, oy, offsets.astype(np.int32), (ox + reach).astype(np.intp), (oy + reach).astype(np.intp))
    for array in vars(arrays).values():
        array.setflags(write=False)
    return arrays
