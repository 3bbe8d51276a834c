"""Which points lie in which boxes: the window query of the nearest-segment searches (a point is measured only
against the segments whose bounding box, grown by a reach, holds it). No I/O.

The points are sorted once by class, then x; each box asks for the run of its class's points within its x range
(two binary searches for all boxes at once) and keeps those within its y range. A point nearer a segment than the
reach lies inside that segment's box grown by the reach, so a nearest segment found among the pairs is the nearest of
all whenever its distance is under the reach.
"""

from __future__ import annotations

import numpy as np


class PointWindows:
    """Points sorted for :meth:`pairs_in_boxes`.

    Args:
        points_px: (M, 2) pixels.
        point_class: (M,) int class of each point (a box holds only points of its own class), or None: one class.
    """

    def __init__(self, points_px: np.ndarray, point_class: np.ndarray | None = None) -> None:
        self.points_px = points_px
        x = points_px[:, 0]
        self._x_range = None
        if point_class is not None and len(x):
            # Each class's x range moved past the one before: a key (class, x) in one sorted array.
            lo, hi = float(x.min()) - 1.0, float(x.max()) + 1.0
            self._x_range, self._class_stride = (lo, hi), (hi - lo) + 10.0
            x = self._keys(x, point_class)
        self.order = np.argsort(x, kind="stable")
        self.sorted_key = x[self.order]

    def _keys(self, x: np.ndarray, of_class: np.ndarray | None) -> np.ndarray:
        """(N,) sort keys of x coordinates in classes (x itself with one class); x clipped to the points' range."""
        if self._x_range is None:
            return x
        lo, hi = self._x_range
        return of_class * self._class_stride + (np.clip(x, lo, hi) - lo)

    def pairs_in_boxes(self, lo: np.ndarray, hi: np.ndarray, box_class: np.ndarray | None = None):
        """Every pair of a box and a point of its class inside it (edges included).

        Args:
            lo, hi: (S, 2) the boxes' lower and upper corners, pixels.
            box_class: (S,) int class of each box (given when the points have classes).

        Returns:
            (box (P,), point (P,)) int indices, box by box, each box's points in x order.
        """
        first = np.searchsorted(self.sorted_key, self._keys(lo[:, 0], box_class), "left")
        stop = np.searchsorted(self.sorted_key, self._keys(hi[:, 0], box_class), "right")
        count = np.maximum(stop - first, 0)
        box = np.repeat(np.arange(len(lo)), count)
        point = self.order[np.arange(len(box)) - np.repeat(np.cumsum(count) - count - first, count)]
        y = self.points_px[point, 1]
        within = (y >= lo[box, 1]) & (y <= hi[box, 1])
        return box[within], point[within]
