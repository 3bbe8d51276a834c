"""Robust losses applied per point inside a stacked factor (iteratively reweighted least squares).

``noiseModel.Robust`` weights a factor by the norm of its whole error vector, which on a
per-frame stacked factor down-weights the frame rather than the outlier point.
So each factor whitens its own residuals and calls :func:`robust_rows` (or :func:`cauchy_rows`):

* linearise path (Jacobians wanted): each point's rows are scaled by ``sqrt(w_k)``, residual and
  Jacobian alike (one IRLS step);
* error-only path: each point's rows are rescaled so that their squared norm is ``2 rho(e_k)``,
  so that GTSAM's ``0.5 |r|^2`` is the loss.

Two losses (:data:`LOSSES`), scale ``c`` in sigmas:

* ``cauchy``: ``rho(e) = c^2 / 2 log(1 + e^2 / c^2)``, ``w = 1 / (1 + e^2 / c^2)``; an outlier's pull
  ``e w`` falls only as ``c^2 / e``: many outliers on one side still add up;
* ``geman-mcclure``: ``rho(e) = c^2 e^2 / (2 (c^2 + e^2))``, ``w = c^4 / (c^2 + e^2)^2``; the pull falls as
  ``c^4 / e^3`` (redescending): points far off stop pulling, so a band of wrongly named points (the ridges of the
  boards named as the far touchline) cannot drag the camera over to them.

Residuals here are already whitened (divided by their sigma).
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


LOSSES = ("cauchy", "geman-mcclure")
"""The per-point losses :func:`robust_rows` applies."""


def check_loss(loss: str, what: str = "line_loss") -> str:
    """``loss`` when it is one of :data:`LOSSES` (a setting's value); ValueError naming the setting ``what``
    otherwise."""
    if loss not in LOSSES:
        raise ValueError(f"{what} must be one of {', '.join(LOSSES)}, got {loss!r}")
    return loss


def geman_mcclure_rho(e2: np.ndarray, scale: float) -> np.ndarray:
    """Geman-McClure cost ``c^2 e^2 / (2 (c^2 + e^2))`` of squared whitened residual norms e2 (N,)."""
    c2 = scale * scale
    return 0.5 * c2 * e2 / (c2 + e2)


def geman_mcclure_weight(e2: np.ndarray, scale: float) -> np.ndarray:
    """IRLS weight ``c^4 / (c^2 + e^2)^2`` of squared whitened residual norms e2 (N,)."""
    c2 = scale * scale
    return (c2 / (c2 + e2)) ** 2


def robust_rows(residuals: np.ndarray, jacobians: list[np.ndarray] | None, scale: float | None,
                loss: str = "cauchy"):
    """Apply the per-point loss ``loss`` (:data:`LOSSES`) to whitened residuals: as :func:`cauchy_rows`."""
    if loss == "cauchy":
        return cauchy_rows(residuals, jacobians, scale)
    if loss != "geman-mcclure":
        raise ValueError(f"unknown robust loss {loss!r} (one of {', '.join(LOSSES)})")
    return _weighted_rows(residuals, jacobians, scale, geman_mcclure_rho, geman_mcclure_weight)


def cauchy_rows(residuals: np.ndarray, jacobians: list[np.ndarray] | None, scale: float | None):
    """Apply the per-point Cauchy loss to whitened residuals.

    Args:
        residuals: (N, d) whitened residuals, one row of d values per point.
        jacobians: list of (N, d, n_i) whitened Jacobians, or None on the error-only path.
        scale: Cauchy scale c in sigmas; None means plain least squares.

    Returns:
        (residuals (N, d), jacobians list or None), reweighted.
    """
    return _weighted_rows(residuals, jacobians, scale, cauchy_rho, cauchy_weight)


def _weighted_rows(residuals, jacobians, scale, rho, weight):
    if scale is None:
        return residuals, jacobians
    e2 = np.einsum("nd,nd->n", residuals, residuals)
    if jacobians is None:
        norm = np.sqrt(e2)
        ratio = np.where(norm > 1e-12, np.sqrt(2.0 * rho(e2, scale)) / np.where(norm > 1e-12, norm, 1.0), 1.0)
        return residuals * ratio[:, None], None
    root_w = np.sqrt(weight(e2, scale))
    return residuals * root_w[:, None], [J * root_w[:, None, None] for J in jacobians]
