"""Batched 3-vectors and 3x3 matrices for the vectorised homography code: cross products without numpy's overhead,
inverses that do not raise on one bad item. No I/O."""

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


def cross3(a, b) -> np.ndarray:
    """a x b over the last axis (of length 3) of two broadcastable arrays: ``np.cross`` with the same products and
    differences (the same numbers) without its checks and axis moves, 2-5x quicker on the few to a few hundred
    vectors the court model crosses at a time (its vanishing points, horizons and rotations).

    Args:
        a, b: (..., 3) arrays (or sequences), broadcast against each other.

    Returns:
        (..., 3) the cross products, in the promoted dtype.
    """
    a, b = np.asarray(a), np.asarray(b)
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    return np.stack([a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0], axis=-1)
