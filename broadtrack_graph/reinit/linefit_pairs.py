"""Which segment of its class's projected polyline each point of a fit is nearest: the association
:mod:`.linefit` asks at every iteration of its fits. No I/O.

A fit's points come in classes (one per pitch marking), each with its polyline (the marking's samples projected),
stacked one class after another (:class:`FitLayout`). The nearest segment is found in two ways that give the same
answer to the bit:

* :meth:`NearestSegments.within_reach`: each point measured only against its class's segments whose bounding box,
  grown by a reach, holds it (:class:`~broadtrack_graph.geometry.point_windows.PointWindows`). Exact for a point
  nearer than the reach to its class's polyline (a nearer segment's box holds it), which is every point once a fit is
  under way; the answer is None when a point is not, and then
* :class:`PointSegmentPairs`: every point against every segment of its class (one flat array of pairs).

Pixels throughout; a segment s joins samples s and s + 1 of the stacked polylines.
"""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.point_windows import PointWindows
from broadtrack_graph.geometry.template import to_segments


class FitLayout:
    """Where each class's points and polyline samples lie in the stacked arrays of a fit.

    Args:
        class_points: (C,) points per class; class_samples: (C,) polyline samples per class (at least 2 each).

    Attributes:
        class_points, class_samples: (C,) int; point_offsets: (C + 1,) each class's first point, then the count;
        class_segment_start: (C,) each class's first segment (its first sample); joins_next: (N - 1,) bool, the
        segment joins two samples of one class; point_class: (M,) and segment_class: (N - 1,) int class of each.
    """

    def __init__(self, class_points, class_samples) -> None:
        self.class_points = np.asarray(class_points, int)
        self.class_samples = samples = np.asarray(class_samples, int)
        self.class_segment_start = np.concatenate([[0], np.cumsum(samples)])[:-1]
        self.point_offsets = np.concatenate([[0], np.cumsum(self.class_points)])
        self.joins_next = np.ones(max(int(samples.sum()) - 1, 0), bool)
        self.joins_next[(self.class_segment_start + samples - 1)[:-1]] = False
        classes = np.arange(len(samples))
        self.point_class = np.repeat(classes, self.class_points)
        self.segment_class = np.repeat(classes, samples)[:-1]


class NearestSegments:
    """The association of a fit's points by the segments within reach (:meth:`within_reach`).

    Args:
        points_px: (M, 2) the fit's points, class after class (``layout``).
        layout: the fit's :class:`FitLayout`.
        reach_px: how far from a segment's bounding box a point is measured (at least 2).
    """

    def __init__(self, points_px: np.ndarray, layout: FitLayout, reach_px: float) -> None:
        self.points_px, self.layout, self.reach_px = points_px, layout, reach_px
        self._windows = PointWindows(points_px, layout.point_class)
        # A point is answered when its distance is under the reach less a pixel: its nearest segment's box holds it
        # whatever the rounding of the sort keys.
        self._answered2 = (reach_px - 1.0) ** 2

    def within_reach(self, uv: np.ndarray, usable: np.ndarray):
        """Each point's nearest usable segment of its class (the first on ties), or None when a point is not within
        reach of one.

        Args:
            uv: (N, 2) the stacked polylines' samples, pixels; usable: (N - 1,) bool, the segments that count.

        Returns:
            (segment (M,) int, t (M,) its parameter in [0, 1] at the point's foot, distance (M,) pixels), each as
            :func:`~broadtrack_graph.geometry.template.to_segments` gives them; or None.
        """
        if not len(self.points_px):
            return None
        segments = np.flatnonzero(usable)
        a, b = uv[segments], uv[segments + 1]
        d = b - a
        length2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-12)
        reach = self.reach_px
        box, point = self._windows.pairs_in_boxes(np.minimum(a, b) - reach, np.maximum(a, b) + reach,
                                                self.layout.segment_class[segments])
        t, dist2 = to_segments(self.points_px[point, 0], self.points_px[point, 1], a[box, 0], a[box, 1], d[box, 0],
                               d[box, 1], length2[box])
        best = np.full(len(self.points_px), np.inf)
        np.minimum.at(best, point, dist2)
        if not (best < self._answered2).all():  # (a NaN is not answered either)
            return None
        # The pairs run box by box, in segment order: a point's first pair at its least distance is its first segment.
        at_best = np.flatnonzero(dist2 == best[point])
        chosen = np.full(len(best), len(dist2))
        np.minimum.at(chosen, point[at_best], at_best)
        return segments[box[chosen]], t[chosen], np.sqrt(best)


class PointSegmentPairs:
    """Every (point, segment of its class's polyline) pair of a fit, in class, segment, point order (each class a
    (segments, points) block): the nearest segment of each point is a minimum over its column of its class's block
    (one pass for all classes, not one per class).

    Args:
        layout: the fit's :class:`FitLayout`.
    """

    def __init__(self, layout: FitLayout) -> None:
        class_points, samples, offsets = layout.class_points, layout.class_samples, layout.point_offsets
        segments = samples - 1
        # (segments,) pairs of each stacked segment: its class's points (none for the join of two classes)
        self.segment_pairs = np.where(layout.joins_next, np.repeat(class_points, samples)[:-1], 0)
        self.segment = np.repeat(np.arange(len(self.segment_pairs)), self.segment_pairs)
        block_start = np.concatenate([[0], np.cumsum(class_points * segments)])
        # the pairs of a segment are its class's points in turn
        segment_first_point = np.repeat(offsets[:-1], samples)[:-1]
        segment_first_pair = np.cumsum(self.segment_pairs) - self.segment_pairs
        self.point = np.arange(len(self.segment)) - np.repeat(segment_first_pair - segment_first_point,
                                                              self.segment_pairs)
        # the pair of each point with its class's first segment, and the pairs between two of its class's segments
        self._first_pair = np.repeat(block_start[:-1] - offsets[:-1], class_points) + \
            np.arange(int(class_points.sum()))
        self._stride = np.repeat(class_points, class_points)
        self._blocks = [(int(block_start[c]), int(block_start[c + 1]), int(k), int(m), int(offsets[c]),
                         int(offsets[c + 1])) for c, (m, k) in enumerate(zip(class_points, segments))]

    def first_minimum(self, values: np.ndarray) -> np.ndarray:
        """(points,) the index into the pairs of each point's smallest value, the first segment on ties (a NaN counts
        as the smallest, as in ``np.argmin``, which each class's block is given)."""
        nearest = np.empty(len(self._first_pair), np.intp)
        for start, stop, k, m, first, last in self._blocks:
            nearest[first:last] = values[start:stop].reshape(k, m).argmin(axis=0)
        nearest *= self._stride
        nearest += self._first_pair
        return nearest
