"""Pairs of points within a distance (broadtrack_graph.geometry.point_pairs): the same pairs as a k-d tree's."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.spatial import cKDTree

from broadtrack_graph.geometry.point_pairs import pairs_within


def _tree_pairs(first, second, distance):
    pairs = cKDTree(first).sparse_distance_matrix(cKDTree(second), distance, output_type="ndarray")
    return {(int(i), int(j)) for i, j in zip(pairs["i"], pairs["j"])}


@pytest.mark.parametrize("seed", range(5))
def test_the_pairs_are_a_k_d_tree_s_on_random_points(seed):
    rng = np.random.default_rng(seed)
    first = rng.uniform(-50, 400, (300, 2))
    second = rng.uniform(-20, 380, (500, 2))
    distance = rng.uniform(0.5, 12.0)
    i, j = pairs_within(first, second, distance)
    assert len(i) == len(set(zip(i.tolist(), j.tolist())))  # no pair twice
    assert set(zip(i.tolist(), j.tolist())) == _tree_pairs(first, second, distance)
    assert len(i) > 0


def test_points_on_cell_edges_and_at_exactly_the_distance_are_paired():
    first = np.array([[0.0, 0.0], [2.0, 2.0], [4.0, 0.0]])
    second = np.array([[2.0, 0.0], [0.0, 2.0], [4.0, 2.0], [6.5, 0.0]])
    i, j = pairs_within(first, second, 2.0)
    assert set(zip(i.tolist(), j.tolist())) == _tree_pairs(first, second, 2.0) == {
        (0, 0), (0, 1), (1, 0), (1, 1), (1, 2), (2, 0), (2, 2)}


def test_no_points_no_pairs_and_a_distance_that_is_not_positive_is_refused():
    none = np.zeros((0, 2))
    some = np.ones((3, 2))
    for first, second in ((none, some), (some, none)):
        i, j = pairs_within(first, second, 1.0)
        assert i.shape == j.shape == (0,)
    with pytest.raises(ValueError, match="distance"):
        pairs_within(some, some, 0.0)
