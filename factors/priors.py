"""Unary priors on one camera state: physical ranges of f and k1, and a Gaussian anchor.

Range prior (3 residuals): f outside [f_min, f_max] (relative excess / sigma_rel),
k1 outside [k1_min, k1_max] (excess / sigma_k1_edge), and a weak pull of k1
towards k1_mean (``(k1 - k1_mean) / sigma_k1``). Zero inside the ranges.
Anchor prior (one residual per entry): ``(s - s0) / sigmas``.
"""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.state import STATE_SIZE
from factors.custom import Residuals, custom_factor


def range_residuals(state, f_range_px, k1_range, edge_sigma_rel, edge_sigma_k1, k1_mean, k1_sigma, want_jacobian=True):
    """Soft range limits on f and k1.

    Returns:
        :class:`~factors.custom.Residuals`: residual (3,); jacobians [(3, 8)] or None.
    """
    f, k1 = float(state[0]), float(state[1])
    f_lo, f_hi = f_range_px
    k_lo, k_hi = k1_range
    residual = np.zeros(3)
    J = np.zeros((3, STATE_SIZE))
    if f < f_lo:
        residual[0] = (f - f_lo) / (f_lo * edge_sigma_rel)
        J[0, 0] = 1.0 / (f_lo * edge_sigma_rel)
    elif f > f_hi:
        residual[0] = (f - f_hi) / (f_hi * edge_sigma_rel)
        J[0, 0] = 1.0 / (f_hi * edge_sigma_rel)
    if k1 < k_lo:
        residual[1] = (k1 - k_lo) / edge_sigma_k1
        J[1, 1] = 1.0 / edge_sigma_k1
    elif k1 > k_hi:
        residual[1] = (k1 - k_hi) / edge_sigma_k1
        J[1, 1] = 1.0 / edge_sigma_k1
    residual[2] = (k1 - k1_mean) / k1_sigma
    J[2, 1] = 1.0 / k1_sigma
    return Residuals(residual, [J] if want_jacobian else None)


def make_range_factor(key, f_range_px, k1_range, edge_sigma_rel, edge_sigma_k1, k1_mean, k1_sigma):
    """CustomFactor keeping f and k1 of one state physical (residual length 3)."""

    def fn(vectors, want_jacobian):
        return range_residuals(
            vectors[0], f_range_px, k1_range, edge_sigma_rel, edge_sigma_k1, k1_mean, k1_sigma, want_jacobian
        )[:2]

    return custom_factor([key], [STATE_SIZE], 3, fn)


def anchor_residuals(state, state0, sigmas, want_jacobian=True):
    """Whitened ``(s - s0) / sigmas`` for any vector variable (camera state, tripod): residual (n,), jacobians [(n, n)]."""
    residual = (np.asarray(state, float) - state0) / sigmas
    return Residuals(residual, [np.diag(1.0 / sigmas)] if want_jacobian else None)


def make_anchor_factor(key, state0, sigmas):
    """Gaussian prior pulling a vector variable towards state0 (residual length len(state0):
    8 for a camera state, 4 for the tripod)."""
    state0 = np.asarray(state0, dtype=float).reshape(-1).copy()
    sigmas = np.asarray(sigmas, dtype=float).reshape(state0.shape).copy()
    size = len(state0)

    def fn(vectors, want_jacobian):
        return anchor_residuals(vectors[0], state0, sigmas, want_jacobian)[:2]

    return custom_factor([key], [size], size, fn)
