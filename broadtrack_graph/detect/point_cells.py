"""Thinning and averaging of marking points on a pixel grid, and the working-to-frame pixel map.

The weight-free detector finds centre-line points at a working size; these helpers bring them
to frame pixels and keep about one (averaged) point per grid cell. Vectorised numpy, no I/O.
"""

from __future__ import annotations

import numpy as np


def work_to_frame_px(points_work_px, scale: float) -> np.ndarray:
    """Working pixels -> frame pixels (pixel centres at integer coordinates in both)."""
    return (np.asarray(points_work_px, float) + 0.5) / scale - 0.5


def pixels_of(points: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """(N, 2) int (col, row): the pixel of each point (pixels, (N, 2)), rounded and clipped to an image of size (w, h)."""
    w, h = size
    return np.column_stack([np.clip(np.round(points[:, 0]).astype(int), 0, w - 1),
                            np.clip(np.round(points[:, 1]).astype(int), 0, h - 1)]).reshape(-1, 2)


def cell_means(points: np.ndarray, spacing: float) -> np.ndarray:
    """The mean of the points in each cell of ``spacing`` pixels: (M, 2), one per occupied cell.

    Along a marking this averages the sub-pixel jitter of neighbouring centre-line points
    (a cell holds a few of them) and spreads the output evenly.
    """
    if len(points) == 0:
        return np.zeros((0, 2))
    cells = np.floor(points / spacing).astype(np.int64)
    _, inverse, counts = np.unique(cells[:, 0] * 1_000_003 + cells[:, 1], return_inverse=True, return_counts=True)
    inverse = inverse.ravel()
    sums = np.column_stack([np.bincount(inverse, points[:, 0]), np.bincount(inverse, points[:, 1])])
    return sums / counts[:, None]


def capped_cell_means(points: np.ndarray, spacing: float, max_points: int) -> np.ndarray:
    """:func:`cell_means` with at most ``max_points`` cells: (M <= max_points, 2).

    A marking's cells lie along a curve, so their count falls about inversely with the cell
    size: too many cells at ``spacing`` are redone once at ``spacing * count / max_points``
    (more averaging per point, same coverage); a rare remainder is subsampled evenly.
    """
    means = cell_means(points, spacing)
    if max_points <= 0 or len(means) <= max_points:
        return means
    means = cell_means(points, spacing * len(means) / max_points)
    if len(means) > max_points:
        means = means[np.linspace(0, len(means) - 1, max_points).round().astype(int)]
    return means


def grid_thin(points: np.ndarray, spacing: float) -> np.ndarray:
    """One point per cell of ``spacing`` pixels (the first in input order)."""
    if len(points) == 0:
        return np.zeros((0, 2))
    cells = np.floor(points / spacing).astype(np.int64)
    _, first = np.unique(cells[:, 0] * 1_000_003 + cells[:, 1], return_index=True)
    return points[np.sort(first)]
