"""Shape checks at public boundaries (one helper, one message form)."""

from __future__ import annotations

import numpy as np


def check_points(array, columns: int, name: str) -> np.ndarray:
    """Return ``array`` as a float (N, columns) array or raise a ValueError naming the shape.

    Args:
        array: array-like of points.
        columns: expected number of columns (2 for pixels, 3 for world points).
        name: argument name for the message.

    Raises:
        ValueError: "points_w: expected (N, 3), got (5, 2)".
    """
    points = np.asarray(array, dtype=float)
    if points.ndim == 1 and points.size == 0:
        return points.reshape(0, columns)
    if points.ndim != 2 or points.shape[1] != columns:
        raise ValueError(f"{name}: expected (N, {columns}), got {points.shape}")
    return points
