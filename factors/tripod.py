"""Tripod factor: the camera's optical axis stays at distance delta from the tripod point T.

``O* = C + ((T - C) . a) a`` is the point of the optical axis (through C along
``a = r3``, the third row of R_cw) closest to T, and ``L_T = delta - |O* - T|``
(metres, paper's cost), divided by sigma_m. The tripod ``[Tx, Ty, Tz, delta]`` is a
4-vector variable (batch) or a constant (online, once estimated).

:func:`tripod_axis_point_residuals` is the full model (the axis passes through
``T - delta r2``), the tracker's default (:data:`DEFAULT_TRIPOD_MODEL`): it separates T from
delta better.
"""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.state import STATE_SIZE, rotation_and_derivatives
from factors.custom import Residuals, custom_factor

TRIPOD_SIZE = 4
MIN_AXIS_DISTANCE_M = 1e-6


def tripod_residual(state: np.ndarray, tripod: np.ndarray, want_jacobian: bool = True):
    """L_T of one camera state.

    Args:
        state: (8,) camera state; tripod: (4,) ``[Tx, Ty, Tz, delta]`` metres.

    Returns:
        :class:`~factors.custom.Residuals`: residual (1,) metres; jacobians [J_state (1, 8), J_tripod (1, 4)] or None.
    """
    s = np.asarray(state, dtype=float)
    T, delta = np.asarray(tripod[:3], dtype=float), float(tripod[3])
    R, dR = rotation_and_derivatives(s[2], s[3], s[4])
    axis = R[2]
    d = s[5:8] - T
    along = float(d @ axis)
    w = d - along * axis  # O* - T
    dist = max(float(np.linalg.norm(w)), MIN_AXIS_DISTANCE_M)
    residual = np.array([delta - dist])
    if not want_jacobian:
        return Residuals(residual, None)
    unit = w / dist
    J_state = np.zeros(STATE_SIZE)
    d_axis = dR[:, 2, :]  # (3 angles, 3): d axis / d angle
    J_state[2:5] = along * (d_axis @ w) / dist
    J_state[5:8] = -unit
    J_tripod = np.array([*unit, 1.0])
    return Residuals(residual, [J_state[None, :], J_tripod[None, :]])


def tripod_axis_point_residuals(state: np.ndarray, tripod: np.ndarray, want_jacobian: bool = True,
                                lambda_prior: tuple[float, float] | None = None):
    """Full tripod model: the optical axis passes through ``O = T - delta r2``.

    ``C - T = -delta r2 + lambda r3`` with lambda free, so the components of
    ``C - T + delta r2`` along r1 and r2 must vanish: residual
    ``[r1 . (C - T), r2 . (C - T) + delta]`` (metres, 2 values). Stronger than L_T (it uses
    the direction of the offset, not only its length).

    Args:
        lambda_prior: optional ``(lambda_mean_m, weight)``: a third residual
            ``weight * (r3 . (C - T) - lambda_mean_m)`` keeps the focal point near its usual
            place on the optical axis (the entrance pupil moves tens of centimetres with zoom).
            At tight zoom, sliding C along the axis trades almost exactly against f, and
            without it biased detections can walk C metres along the axis.
            ``weight = sigma_m / lambda_sigma_m`` gives it the sigma lambda_sigma_m once the
            factor divides by sigma_m.

    Returns:
        :class:`~factors.custom.Residuals`: residual (2,) or (3,) metres; jacobians [J_state (2 or 3, 8),
        J_tripod (2 or 3, 4)] or None.
    """
    s = np.asarray(state, dtype=float)
    T, delta = np.asarray(tripod[:3], dtype=float), float(tripod[3])
    R, dR = rotation_and_derivatives(s[2], s[3], s[4])
    d = s[5:8] - T
    rows = 2 if lambda_prior is None else 3
    residual = np.array([R[0] @ d, R[1] @ d + delta])
    if lambda_prior is not None:
        lambda_mean_m, weight = lambda_prior
        residual = np.append(residual, weight * (R[2] @ d - lambda_mean_m))
    if not want_jacobian:
        return Residuals(residual, None)
    J_state = np.zeros((rows, STATE_SIZE))
    J_state[:, 2:5] = (dR[:, :rows, :] @ d).T  # (rows, 3 angles)
    J_state[:, 5:8] = R[:rows]
    J_tripod = np.zeros((rows, TRIPOD_SIZE))
    J_tripod[:, :3] = -R[:rows]
    J_tripod[1, 3] = 1.0
    if lambda_prior is not None:
        J_state[2] *= lambda_prior[1]
        J_tripod[2] *= lambda_prior[1]
    return Residuals(residual, [J_state, J_tripod])


TRIPOD_MODELS = ("distance", "axis_point")
"""``distance``: the paper's L_T (1 residual); ``axis_point``: the full model (2 residuals)."""

DEFAULT_TRIPOD_MODEL = "axis_point"
"""The model the tracker uses unless told otherwise (``GraphConfig``'s default is this one)."""


def _model_function(model: str, lambda_prior: tuple[float, float] | None = None):
    """(residual function, residual length) of a tripod model; the lambda prior applies to axis_point
    only (the distance model measures no place along the axis)."""
    if model == "distance":
        return tripod_residual, 1
    if model == "axis_point":
        if lambda_prior is None:
            return tripod_axis_point_residuals, 2

        def with_lambda(state, tripod, want):
            return tripod_axis_point_residuals(state, tripod, want, lambda_prior)
        return with_lambda, 3
    raise ValueError(f"unknown tripod model '{model}'; choose one of {TRIPOD_MODELS}")


def _lambda_weight(sigma_m: float, lambda_prior_m: tuple[float, float] | None) -> tuple[float, float] | None:
    """(mean, sigma) of lambda -> (mean, weight) for :func:`tripod_axis_point_residuals`."""
    if lambda_prior_m is None:
        return None
    mean_m, sigma_lambda_m = lambda_prior_m
    return float(mean_m), float(sigma_m) / float(sigma_lambda_m)


def make_tripod_factor(state_key: int, tripod_key: int, sigma_m: float, model: str = DEFAULT_TRIPOD_MODEL,
                       lambda_prior_m: tuple[float, float] | None = None):
    """CustomFactor between a camera state and the tripod variable (residual length 1, 2 or 3).

    lambda_prior_m: optional (mean, sigma) of lambda, metres (axis_point model only).
    """
    residual_fn, dim = _model_function(model, _lambda_weight(sigma_m, lambda_prior_m))

    def fn(vectors, want_jacobian):
        r, Js, _ = residual_fn(vectors[0], vectors[1], want_jacobian)
        return r / sigma_m, None if Js is None else [J / sigma_m for J in Js]

    return custom_factor([state_key, tripod_key], [STATE_SIZE, TRIPOD_SIZE], dim, fn)


def make_fixed_tripod_factor(state_key: int, tripod_vector: np.ndarray, sigma_m: float, model: str = DEFAULT_TRIPOD_MODEL,
                             lambda_prior_m: tuple[float, float] | None = None):
    """CustomFactor on one camera state with the tripod held fixed (online use)."""
    tripod_vector = np.asarray(tripod_vector, dtype=float).reshape(TRIPOD_SIZE).copy()
    residual_fn, dim = _model_function(model, _lambda_weight(sigma_m, lambda_prior_m))

    def fn(vectors, want_jacobian):
        r, Js, _ = residual_fn(vectors[0], tripod_vector, want_jacobian)
        return r / sigma_m, None if Js is None else [Js[0] / sigma_m]

    return custom_factor([state_key], [STATE_SIZE], dim, fn)
