"""Batched 3x3 matrices for the vectorised homography code: inverses that do not raise on one bad item. No I/O."""

from __future__ import annotations

import numpy as np


def inverses(M: np.ndarray) -> np.ndarray:
    """(K, 3, 3) inverses of the (K, 3, 3) matrices ``M``; NaN where a matrix is singular (its determinant under
    1e-12 times its largest entry cubed). One degenerate item (three collinear points of a basis, parallel lines)
    raises nothing and spoils only its own inverse, so a whole batch of hypotheses is inverted at once."""
    M = np.asarray(M, float)
    with np.errstate(invalid="ignore"):  # a NaN item's determinant is NaN: singular
        singular = ~(np.abs(np.linalg.det(M)) >= 1e-12 * np.maximum(np.abs(M).max(axis=(1, 2)) ** 3, 1e-300))
    safe = np.where(singular[:, None, None], np.eye(3), M)
    return np.where(singular[:, None, None], np.nan, np.linalg.inv(safe))
