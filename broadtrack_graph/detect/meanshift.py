"""Mean-shift thinning of marking pixels: many pixels across a thick line -> points on its centre.

Each point moves to the mean of the input pixels within ``bandwidth_px`` (flat kernel)
for a few iterations, which collapses the cross-section of a line onto its centre;
the moved points are then merged on a grid of ``spacing_px`` so that the output is
evenly spread along the marking. Neighbourhoods come from k-d trees (scipy) and one sparse product per step. No I/O.
"""

from __future__ import annotations

import numpy as np
from scipy.sparse import diags
from scipy.spatial import cKDTree

from broadtrack_graph.geometry.shapes import check_points


def _neighbour_means(points: np.ndarray, queries: np.ndarray, radius: float, weights: np.ndarray | None):
    """Weighted mean of the input points within ``radius`` of each query, and the neighbour weight sum."""
    tree_points = cKDTree(points)
    tree_queries = cKDTree(queries)
    S = tree_queries.sparse_distance_matrix(tree_points, radius, output_type="coo_matrix").tocsr()
    S.data[:] = 1.0  # flat kernel (the query's own point has distance 0 and may be absent: added below)
    w = np.ones(len(points)) if weights is None else np.asarray(weights, float)
    S = S @ diags(w)
    count = np.asarray(S.sum(axis=1)).ravel()
    total = S @ points
    return total, count


def mean_shift_thin(points_px: np.ndarray, bandwidth_px: float = 4.0, spacing_px: float = 4.0,
                    iterations: int = 3, weights: np.ndarray | None = None) -> np.ndarray:
    """Thin marking pixels to evenly spaced centre-line points.

    Args:
        points_px: (N, 2) pixels of one class (or of all markings).
        bandwidth_px: flat-kernel radius; about the largest line half-width expected.
        spacing_px: output points are merged on a grid of this size.
        iterations: mean-shift steps.
        weights: (N,) optional per-pixel weights (e.g. segmentation scores).

    Returns:
        (M, 2) thinned points, M <= N.
    """
    points = check_points(points_px, 2, "points_px")
    if len(points) == 0:
        return points.copy()
    # Seeds: one per spacing cell, so the cost does not grow with line thickness.
    cells = np.floor(points / spacing_px).astype(np.int64)
    _, first = np.unique(cells[:, 0] * 1_000_003 + cells[:, 1], return_index=True)
    seeds = points[np.sort(first)].copy()
    for _ in range(iterations):
        total, count = _neighbour_means(points, seeds, bandwidth_px, weights)
        ok = count > 0
        seeds[ok] = total[ok] / count[ok, None]
    merged = np.floor(seeds / (0.5 * spacing_px)).astype(np.int64)
    _, keep = np.unique(merged[:, 0] * 1_000_003 + merged[:, 1], return_index=True)
    return seeds[np.sort(keep)]
