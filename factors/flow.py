"""Optical-flow factor between the cameras of frames t-1 and t.

Each match (u_prev, u_cur): u_prev is back-projected with camera t-1 onto the ground
plane z = 0, and the ground point must reproject onto u_cur with camera t. Both
cameras are variables. Residual ``(project_t(X) - u_cur) / sigma_px`` (2 values per
match), per-match Cauchy loss. Matches whose ray misses the ground in front of
camera t-1, or whose ground point is behind camera t, get a constant residual.
"""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.distortion import undistort_normalized
from broadtrack_graph.geometry.state import STATE_SIZE, project_state, rotation_and_derivatives
from factors.custom import Residuals, custom_factor
from factors.robust import INVALID_RESIDUAL_SIGMAS, cauchy_rows

MAX_GROUND_DISTANCE_M = 1000.0
"""Rays meeting the ground further than this from camera t-1 are not used (near-horizontal)."""


def ground_points(state_prev: np.ndarray, uv_prev_px: np.ndarray, width_px: int, height_px: int, want_jacobian: bool = True):
    """Back-project pixels of camera t-1 onto z = 0.

    Args:
        state_prev: (8,) camera state of frame t-1.
        uv_prev_px: (N, 2) pixels.

    Returns:
        points_w: (N, 3) metres on z = 0 (finite dummies where invalid).
        dX: (N, 3, 8) d points_w / d state_prev, or None.
        hits: (N,) bool, the ray meets the ground in front of the camera within 1 km.
    """
    s = np.asarray(state_prev, dtype=float)
    focal, k1 = s[0], s[1]
    R, dR = rotation_and_derivatives(s[2], s[3], s[4])
    centre = np.array([width_px / 2.0, height_px / 2.0])
    xy_d = (uv_prev_px - centre) / focal
    xy_n = undistort_normalized(xy_d, k1)
    count = len(xy_n)
    ray_c = np.concatenate([xy_n, np.ones((count, 1))], axis=1)
    ray_w = ray_c @ R  # R^T applied to each row
    rz = ray_w[:, 2]
    safe_rz = np.where(np.abs(rz) > 1e-9, rz, 1e-9)
    distance = -s[7] / safe_rz
    hits = (distance > 0) & (distance * np.linalg.norm(ray_w, axis=1) < MAX_GROUND_DISTANCE_M)
    q = ray_w[:, :2] / safe_rz[:, None]
    points_w = np.zeros((count, 3))
    points_w[:, :2] = s[5:7] - s[7] * q
    points_w[~hits, :2] = s[5:7]
    if not want_jacobian:
        return points_w, None, hits
    x, y = xy_n[:, 0], xy_n[:, 1]
    r2 = x * x + y * y
    g = 1.0 + k1 * r2
    D = np.empty((count, 2, 2))  # d xy_d / d xy_n
    D[:, 0, 0] = g + 2 * k1 * x * x
    D[:, 1, 1] = g + 2 * k1 * y * y
    D[:, 0, 1] = D[:, 1, 0] = 2 * k1 * x * y
    det = D[:, 0, 0] * D[:, 1, 1] - D[:, 0, 1] * D[:, 1, 0]
    Dinv = np.empty_like(D)
    Dinv[:, 0, 0] = D[:, 1, 1] / det
    Dinv[:, 1, 1] = D[:, 0, 0] / det
    Dinv[:, 0, 1] = -D[:, 0, 1] / det
    Dinv[:, 1, 0] = -D[:, 1, 0] / det
    rhs = np.stack([-xy_d / focal, -xy_n * r2[:, None]], axis=2)  # (N, 2, 2): columns f, k1
    dxn_dfk = Dinv @ rhs  # (N, 2, 2): d xy_n / d (f, k1)
    # ground xy = C_xy - Cz q, q = ray_xy / ray_z: d q / d ray = (1 / rz) [[1, 0, -qx], [0, 1, -qy]]
    inv_rz = 1.0 / safe_rz
    dX = np.zeros((count, 3, STATE_SIZE))
    dXxy_dray = np.zeros((count, 2, 3))
    dXxy_dray[:, 0, 0] = -s[7] * inv_rz
    dXxy_dray[:, 1, 1] = -s[7] * inv_rz
    dXxy_dray[:, :, 2] = s[7] * q * inv_rz[:, None]
    dXxy_dxn = dXxy_dray @ R[:2].T  # ray_w = R^T [x_n, 1]: d ray / d x_n = R[:2].T (3, 2)
    dX[:, :2, 0:2] = dXxy_dxn @ dxn_dfk
    dray_dangles = np.tensordot(ray_c, dR, axes=([1], [1])).transpose(0, 2, 1)  # (N, 3, 3): (ray_c @ dR_k)_i
    dX[:, :2, 2:5] = dXxy_dray @ dray_dangles
    dX[:, 0, 5] = 1.0
    dX[:, 1, 6] = 1.0
    dX[:, :2, 7] = -q
    dX[~hits] = 0.0
    return points_w, dX, hits


def flow_residuals(state_prev, state_cur, uv_prev_px, uv_cur_px, width_px, height_px, want_jacobian=True,
                   previous_fixed=False):
    """Transfer errors of flow matches through the ground plane.

    Args:
        previous_fixed: camera t-1 is held (a prediction of camera t): its Jacobian is not made (None).

    Returns:
        :class:`~factors.custom.Residuals`: residual (N, 2) predicted minus observed pixel in
        frame t; jacobians [J_prev, J_cur], (N, 2, 8) each, or None; valid (N,) bool.
    """
    points_w, dX, hits = ground_points(state_prev, uv_prev_px, width_px, height_px,
                                       want_jacobian and not previous_fixed)
    uv_hat, J_cur, in_front = project_state(state_cur, points_w, width_px, height_px, want_jacobian)
    valid = hits & in_front
    residual = np.where(valid[:, None], uv_hat - uv_cur_px, 0.0)
    if not want_jacobian:
        return Residuals(residual, None, valid)
    J_prev = None
    if not previous_fixed:
        # d uv / d X_w is minus the position columns of J_cur (project_state_dX's numbers, negated exactly;
        # J_cur's rows behind camera t are zero, and those matches are not valid).
        J_prev = -(np.ascontiguousarray(J_cur[:, :, 5:8]) @ dX)
        J_prev[~valid] = 0.0
    J_cur[~valid] = 0.0
    return Residuals(residual, [J_prev, J_cur], valid)


def make_flow_factor(key_prev, key_cur, uv_prev_px, uv_cur_px, width_px, height_px, sigma_px, cauchy_scale):
    """CustomFactor on the states of frames t-1 and t: all flow matches (residual length 2N)."""
    uv_prev_px = np.ascontiguousarray(uv_prev_px, dtype=float)
    uv_cur_px = np.ascontiguousarray(uv_cur_px, dtype=float)
    count = len(uv_prev_px)

    def fn(vectors, want_jacobian):
        r, Js, valid = flow_residuals(vectors[0], vectors[1], uv_prev_px, uv_cur_px, width_px, height_px, want_jacobian)
        r = np.where(valid[:, None], r / sigma_px, INVALID_RESIDUAL_SIGMAS / np.sqrt(2.0))
        Js = None if Js is None else [J / sigma_px for J in Js]
        r, Js = cauchy_rows(r, Js, cauchy_scale)
        if Js is None:
            return r.reshape(-1), None
        return r.reshape(-1), [J.reshape(2 * count, STATE_SIZE) for J in Js]

    return custom_factor([key_prev, key_cur], [STATE_SIZE, STATE_SIZE], 2 * count, fn)
