"""Whether a marking ridge lies on grass: grass on both sides of it, across the line. No I/O.

Paint lies on grass, so across a marking, just past its edges, there is grass on both sides. A bright ridge between
two other surfaces (the gap between two coloured blocks of a crowd or a stand that the field map takes in where it
meets the grass, a board's seam, a kit's stripe) has grass on one side at most. The ridge's own width is read from
its candidate pixels (the top-hat's pixels over the threshold, :mod:`.ridges`): the centre-line point's distance to
the nearest pixel that is no candidate is the ridge's half width there; along the ridge's normal, the pixels that
far plus ``margin_px`` on each side must be grass. A ridge wider than the reach, a side beyond the image and a point
without a normal (its Hessian gives none) are not held against the point.
"""

from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.detect.point_cells import pixels_of


def grass_beside(points_px: np.ndarray, normals: np.ndarray, candidates: np.ndarray, grass: np.ndarray,
                 margin_px: float, reach_px: float = 12.0) -> np.ndarray:
    """(N,) bool: the centre-line points with grass on both sides across their ridge (module docstring).

    The ridge's half width at a point is its distance to the nearest pixel that is no candidate (one distance
    transform of the candidate map for all points); the grass is read that far plus ``margin_px`` along the normal,
    each way.

    Args:
        points_px: (N, 2) sub-pixel centre-line points (x, y), pixels of the maps.
        normals: (N, 2) unit normals across the ridge at each point ((0, 0): none).
        candidates: (h, w) uint8, non-zero on the ridge's candidate pixels.
        grass: (h, w) uint8, non-zero on grass.
        margin_px: how far past the ridge's edge the grass is read.
        reach_px: a ridge whose half width is more is not judged.
    """
    n = len(points_px)
    if n == 0:
        return np.zeros(0, bool)
    h, w = grass.shape
    to_edge = cv2.distanceTransform(np.asarray(candidates, np.uint8), cv2.DIST_L2, 3)  # to the nearest zero pixel
    col, row = pixels_of(points_px, (w, h)).T
    half_width = to_edge[row, col]
    unjudged = (half_width > reach_px) | (np.hypot(normals[:, 0], normals[:, 1]) < 0.5)
    both = np.ones(n, bool)
    for sign in (1.0, -1.0):
        probe = np.rint(points_px + sign * (half_width + margin_px)[:, None] * normals).astype(int)
        x, y = probe[:, 0], probe[:, 1]
        beyond = (x < 0) | (x >= w) | (y < 0) | (y >= h)
        both &= beyond | (grass[np.clip(y, 0, h - 1), np.clip(x, 0, w - 1)] > 0)
    return unjudged | both
