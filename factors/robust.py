"""Cauchy loss applied per point inside a stacked factor (iteratively reweighted least squares).

``noiseModel.Robust`` weights a factor by the norm of its whole error vector, which on a
per-frame stacked factor down-weights the frame rather than the outlier point.
So each factor whitens its own residuals and calls :func:`cauchy_rows`:

* linearise path (Jacobians wanted): each point's rows are scaled by ``sqrt(w_k)``,
  ``w_k = 1 / (1 + e_k^2 / c^2)``, residual and Jacobian alike (one IRLS step);
* error-only path: each point's rows are rescaled so that their squared norm is
  ``2 rho(e_k)``, ``rho(e) = c^2 / 2 log(1 + e^2 / c^2)``, so that GTSAM's ``0.5 |r|^2`` is the
  Cauchy cost.

Residuals here are already whitened (divided by their sigma); ``c`` is in sigmas.
"""

from __future__ import annotations

import numpy as np

INVALID_RESIDUAL_SIGMAS = 10.0
"""Whitened residual given to a point with nothing to measure it against (constant: no gradient)."""


def cauchy_rho(e2: np.ndarray, scale: float) -> np.ndarray:
    """Cauchy cost ``c^2 / 2 log(1 + e^2 / c^2)`` of squared whitened residual norms e2 (N,)."""
    c2 = scale * scale
    return 0.5 * c2 * np.log1p(e2 / c2)


def cauchy_weight(e2: np.ndarray, scale: float) -> np.ndarray:
    """IRLS weight ``1 / (1 + e^2 / c^2)`` of squared whitened residual norms e2 (N,)."""
    return 1.0 / (1.0 + e2 / (scale * scale))


def cauchy_rows(residuals: np.ndarray, jacobians: list[np.ndarray] | None, scale: float | None):
    """Apply the per-point Cauchy loss to whitened residuals.

    Args:
        residuals: (N, d) whitened residuals, one row of d values per point.
        jacobians: list of (N, d, n_i) whitened Jacobians, or None on the error-only path.
        scale: Cauchy scale c in sigmas; None means plain least squares.

    Returns:
        (residuals (N, d), jacobians list or None), reweighted.
    """
    if scale is None:
        return residuals, jacobians
    e2 = np.einsum("nd,nd->n", residuals, residuals)
    if jacobians is None:
        norm = np.sqrt(e2)
        ratio = np.where(norm > 1e-12, np.sqrt(2.0 * cauchy_rho(e2, scale)) / np.where(norm > 1e-12, norm, 1.0), 1.0)
        return residuals * ratio[:, None], None
    root_w = np.sqrt(cauchy_weight(e2, scale))
    return residuals * root_w[:, None], [J * root_w[:, None, None] for J in jacobians]
