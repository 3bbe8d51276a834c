"""Points in boxes (broadtrack_graph.geometry.point_windows): every pair a brute-force test finds, in box then x
order, with and without classes."""

from __future__ import annotations

import numpy as np
import pytest

from broadtrack_graph.geometry.point_windows import PointWindows


def _brute_force(points, lo, hi, point_class=None, box_class=None):
    inside = np.all((points[None] >= lo[:, None]) & (points[None] <= hi[:, None]), axis=2)  # (boxes, points)
    if point_class is not None:
        inside &= box_class[:, None] == point_class[None]
    box, point = np.nonzero(inside)
    return box, point


@pytest.mark.parametrize("seed", range(4))
@pytest.mark.parametrize("with_classes", [False, True])
def test_the_pairs_are_a_brute_force_test_s_in_box_then_x_order(seed, with_classes):
    rng = np.random.default_rng(seed)
    points = rng.uniform(0, 400, (300, 2))
    points[:20] = np.round(points[:20])  # points on box edges below
    centre, half = rng.uniform(-50, 450, (80, 2)), rng.uniform(0, 40, (80, 2))
    lo, hi = centre - half, centre + half
    lo[:10], hi[:10] = points[:10], points[10:20]  # boxes from one point to another: both on the edges
    lo[70:], hi[70:] = -1e9, 1e9  # boxes far wider than the points' range
    point_class = rng.integers(0, 5, len(points)) if with_classes else None
    box_class = rng.integers(0, 5, len(lo)) if with_classes else None
    box, point = PointWindows(points, point_class).pairs_in_boxes(lo, hi, box_class)
    want_box, want_point = _brute_force(points, lo, hi, point_class, box_class)
    assert len(box) == len(want_box) > 0
    assert set(zip(box.tolist(), point.tolist())) == set(zip(want_box.tolist(), want_point.tolist()))
    assert np.all(np.diff(box) >= 0)  # box by box ...
    same_box = box[1:] == box[:-1]
    keys = points[point, 0] if point_class is None else point_class[point] * 1e4 + points[point, 0]
    assert np.all(np.diff(keys)[same_box] >= 0)  # ... each box's points in (class and) x order


def test_no_points_and_empty_boxes_give_no_pairs():
    none = PointWindows(np.zeros((0, 2)), np.zeros(0, int))
    box, point = none.pairs_in_boxes(np.zeros((3, 2)), np.ones((3, 2)), np.zeros(3, int))
    assert len(box) == len(point) == 0
    some = PointWindows(np.array([[1.0, 1.0], [5.0, 5.0]]))
    box, point = some.pairs_in_boxes(np.array([[2.0, 0.0], [0.0, 2.0]]), np.array([[1.5, 9.0], [9.0, 1.5]]))
    assert len(box) == 0  # lo above hi: empty boxes
