"""Pairs of points of two sets within a distance of each other, found on a grid of cells. No I/O.

Every point of the second set is filed under its square cell of the distance's size; a pair within the distance lies
in the same cell or in one of the 8 around it, so each point of the first set looks in 9 cells (a sorted search each,
all points at once) and the candidates are then measured. The same pairs as a k-d tree's sparse distance matrix,
without building one (or importing a library for it: the process that prepares the frames uses this).
"""

from __future__ import annotations

import numpy as np


def pairs_within(first: np.ndarray, second: np.ndarray, distance: float) -> tuple[np.ndarray, np.ndarray]:
    """Every pair (i, j) with ``|first[i] - second[j]| <= distance``.

    Args:
        first: (N, 2) points (any unit, say pixels).
        second: (M, 2) points, in the same unit.
        distance: the largest distance of a pair (> 0), in that unit.

    Returns:
        (P,) int indices into ``first`` and (P,) int indices into ``second``, in no particular order.
    """
    first = np.asarray(first, float).reshape(-1, 2)
    second = np.asarray(second, float).reshape(-1, 2)
    empty = np.zeros(0, np.intp)
    if not len(first) or not len(second):
        return empty, empty
    if not distance > 0:
        raise ValueError(f"distance must be > 0, got {distance}")
    low = np.minimum(first.min(axis=0), second.min(axis=0))
    first_cells = np.floor((first - low) / distance).astype(np.int64) + 1  # >= 1: a cell to the left stays >= 0
    second_cells = np.floor((second - low) / distance).astype(np.int64) + 1
    rows = int(max(first_cells[:, 1].max(), second_cells[:, 1].max())) + 2
    second_keys = second_cells[:, 0] * rows + second_cells[:, 1]
    order = np.argsort(second_keys, kind="stable")
    sorted_keys = second_keys[order]
    found_i, found_j = [], []
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            keys = (first_cells[:, 0] + dx) * rows + (first_cells[:, 1] + dy)
            start = np.searchsorted(sorted_keys, keys, side="left")
            counts = np.searchsorted(sorted_keys, keys, side="right") - start
            total = int(counts.sum())
            if not total:
                continue
            i = np.repeat(np.arange(len(first)), counts)
            # the k-th candidate of point i is sorted place start[i] + k
            places = np.arange(total) - np.repeat(np.cumsum(counts) - counts, counts) + np.repeat(start, counts)
            j = order[places]
            offset = first[i] - second[j]
            near = np.einsum("ij,ij->i", offset, offset) <= distance * distance
            found_i.append(i[near])
            found_j.append(j[near])
    if not found_i:
        return empty, empty
    return np.concatenate(found_i), np.concatenate(found_j)
