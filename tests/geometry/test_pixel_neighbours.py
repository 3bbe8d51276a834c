"""The grid pixels within a distance of sub-pixel points (geometry/pixel_neighbours.py), against a k-d tree."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import cKDTree

from broadtrack_graph.geometry.pixel_neighbours import pixels_within, reachable_offsets


@pytest.mark.parametrize("tolerance_px", [2.5, 1.0, 3.2])
def test_pixels_within_a_tolerance_are_the_pairs_a_kd_tree_finds(tolerance_px):
    rng = np.random.default_rng(7)
    points = rng.uniform(-5.0, 70.0, (400, 2))
    points[:150] = np.round(points[:150] * 2.0) / 2.0  # on pixels and half-way between: the strict boundary
    w, h = 64, 48
    near, pixel = pixels_within(points, (w, h), tolerance_px)
    rows, cols = np.mgrid[0:h, 0:w]
    grid = np.column_stack([cols.ravel(), rows.ravel()]).astype(float)
    expected = cKDTree(grid).query_ball_point(points, tolerance_px + 1.0)
    for k in range(len(points)):
        found = set(pixel[k][near[k]].tolist())
        truth = {j for j in expected[k] if np.sum((grid[j] - points[k]) ** 2) < tolerance_px**2}
        assert found == truth


def test_the_offsets_are_every_pixel_a_point_of_the_cell_can_reach():
    """Every pixel that a point of the unit cell past floor(point) lies strictly within the tolerance of is among the
    offsets (checked on a fine grid of the cell), and each offset's place along each axis gives it back."""
    for tolerance_px in (0.5, 1.0, 2.5, 3.2):
        reach = reachable_offsets(tolerance_px)
        cell = np.stack(np.meshgrid(np.linspace(0, 0.999, 40), np.linspace(0, 0.999, 40)), axis=-1).reshape(-1, 1, 2)
        span = np.arange(-5, 7)
        pixels = np.stack(np.meshgrid(span, span), axis=-1).reshape(1, -1, 2)
        reached = (((pixels - cell) ** 2).sum(axis=-1) < tolerance_px ** 2).any(axis=0)
        assert set(map(tuple, pixels[0][reached].tolist())) <= set(zip(reach.x.tolist(), reach.y.tolist()))
        assert np.array_equal(reach.axis[reach.x_index], reach.x) and np.array_equal(reach.axis[reach.y_index], reach.y)
