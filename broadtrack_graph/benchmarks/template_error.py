"""How far an estimated camera is from the truth, in the image: the pixel distances between the pitch's points as
each draws them, over the points the true camera sees (the benches' template error; the SoccerNet metric reads
markings, this reads cameras). No I/O."""

from __future__ import annotations

import numpy as np


def template_errors_px(estimate, truth, points_w: np.ndarray) -> np.ndarray:
    """Pixel distances between the marking points projected by two cameras, over the points the truth sees.

    Returns (K,) distances (inf where the estimate puts a point behind it); empty when the truth sees none.
    """
    from broadtrack_graph.graph.simulate import visible_mask

    uv_true, keep = visible_mask(truth, points_w)
    if not keep.any():
        return np.zeros(0)
    uv_est, front = estimate.project(points_w[keep])
    d = np.linalg.norm(uv_est - uv_true[keep], axis=1)
    d[~front] = np.inf
    return d


def median_template_error_px(estimate, truth, points_w: np.ndarray) -> float | None:
    """Median of :func:`template_errors_px` (None: no estimate, or the truth sees none of the points)."""
    if estimate is None:
        return None
    errors = template_errors_px(estimate, truth, points_w)
    return float(np.median(errors)) if len(errors) else None
