"""Motion priors between consecutive camera states (Gaussian, whitened inside).

Random walk between frames t-1 and t (8 residuals):
``[log f_t - log f_{t-1}, dk1, dpan, dtilt, droll, dCx, dCy, dCz] / sigmas``.
Smoothness (second difference) over t-2, t-1, t for log f, pan, tilt, roll (4 residuals).
Sigmas are per frame and given by the caller (graph config).
"""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.state import STATE_SIZE
from factors.custom import Residuals, custom_factor

SMOOTH_INDICES = (0, 2, 3, 4)
"""State entries constrained by the smoothness factor (f through log f, pan, tilt, roll)."""


def random_walk_residuals(state_prev: np.ndarray, state_cur: np.ndarray, sigmas: np.ndarray, want_jacobian=True):
    """Whitened first differences.

    Args:
        sigmas: (8,) per-frame sigmas: relative zoom (log f), k1, pan, tilt, roll (rad), Cx, Cy, Cz (m).

    Returns:
        :class:`~factors.custom.Residuals`: residual (8,); jacobians [J_prev, J_cur], (8, 8) each, or None.
    """
    a, b = np.asarray(state_prev, float), np.asarray(state_cur, float)
    diff = b - a
    diff[0] = np.log(b[0] / a[0])
    residual = diff / sigmas
    if not want_jacobian:
        return Residuals(residual, None)
    J_cur = np.diag(1.0 / sigmas)
    J_prev = -J_cur.copy()
    J_cur[0, 0] = 1.0 / (b[0] * sigmas[0])
    J_prev[0, 0] = -1.0 / (a[0] * sigmas[0])
    return Residuals(residual, [J_prev, J_cur])


def smoothness_residuals(s0, s1, s2, sigmas: np.ndarray, want_jacobian=True):
    """Whitened second differences of (log f, pan, tilt, roll) over three consecutive states.

    Args:
        sigmas: (4,) per-frame^2 sigmas for log f, pan, tilt, roll.

    Returns:
        :class:`~factors.custom.Residuals`: residual (4,); jacobians [J0, J1, J2], (4, 8) each, or None.
    """
    states = [np.asarray(s, float) for s in (s0, s1, s2)]
    values = [np.array([np.log(s[0]), s[2], s[3], s[4]]) for s in states]
    residual = (values[0] - 2.0 * values[1] + values[2]) / sigmas
    if not want_jacobian:
        return Residuals(residual, None)
    Js = []
    for coeff, s in zip((1.0, -2.0, 1.0), states):
        J = np.zeros((4, STATE_SIZE))
        J[0, 0] = coeff / (s[0] * sigmas[0])
        for row, col in enumerate(SMOOTH_INDICES[1:], start=1):
            J[row, col] = coeff / sigmas[row]
        Js.append(J)
    return Residuals(residual, Js)


def make_random_walk_factor(key_prev: int, key_cur: int, sigmas) -> "gtsam.CustomFactor":  # noqa: F821
    """CustomFactor between consecutive states (residual length 8)."""
    sigmas = np.asarray(sigmas, dtype=float).reshape(STATE_SIZE).copy()

    def fn(vectors, want_jacobian):
        return random_walk_residuals(vectors[0], vectors[1], sigmas, want_jacobian)[:2]

    return custom_factor([key_prev, key_cur], [STATE_SIZE, STATE_SIZE], STATE_SIZE, fn)


def make_smoothness_factor(key0: int, key1: int, key2: int, sigmas) -> "gtsam.CustomFactor":  # noqa: F821
    """CustomFactor over three consecutive states (residual length 4)."""
    sigmas = np.asarray(sigmas, dtype=float).reshape(4).copy()

    def fn(vectors, want_jacobian):
        return smoothness_residuals(vectors[0], vectors[1], vectors[2], sigmas, want_jacobian)[:2]

    return custom_factor([key0, key1, key2], [STATE_SIZE] * 3, 4, fn)
