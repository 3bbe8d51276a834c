"""Vectorised projection of the tracker's 8-vector state with its analytic Jacobian.

State (SoccerNet convention, DESIGN.md): ``s = [f, k1, pan, tilt, roll, Cx, Cy, Cz]``
(pixels, unitless, radians, metres). ``R_cw = (Rz(pan) Rx(tilt) Rz(roll))^T``,
``Xc = R_cw (X_w - C_w)``, ``x_n = Xc_xy / Xc_z``, ``uv = f (1 + k1 r^2) x_n + p`` with
``p = (W / 2, H / 2)``. Pure numpy, no I/O.
"""

from __future__ import annotations

import math

import numpy as np

STATE_SIZE = 8
"""Length of the camera state vector."""

STATE_NAMES: tuple[str, ...] = ("f_px", "k1", "pan_rad", "tilt_rad", "roll_rad", "Cx_m", "Cy_m", "Cz_m")
"""Parameter order of the camera state (columns of every camera Jacobian)."""

BEHIND_CAMERA_Z = 1e-3
"""Camera-frame depth (metres) at or below which a point counts as behind the camera."""


def _rz(a: float) -> tuple[np.ndarray, np.ndarray]:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]), np.array([[-s, -c, 0.0], [c, -s, 0.0], [0.0, 0.0, 0.0]])


def _rx(a: float) -> tuple[np.ndarray, np.ndarray]:
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]]), np.array([[0.0, 0.0, 0.0], [0.0, -s, -c], [0.0, c, -s]])


def rotation_and_derivatives(pan_rad: float, tilt_rad: float, roll_rad: float) -> tuple[np.ndarray, np.ndarray]:
    """World-to-camera rotation and its derivatives with respect to pan, tilt, roll.

    Returns:
        R_cw: (3, 3).
        dR: (3, 3, 3), ``dR[i]`` = d R_cw / d angle_i for angles (pan, tilt, roll).
    """
    P, dP = _rz(pan_rad)
    T, dT = _rx(tilt_rad)
    Q, dQ = _rz(roll_rad)
    R = (P @ T @ Q).T
    dR = np.stack([(dP @ T @ Q).T, (P @ dT @ Q).T, (P @ T @ dQ).T])
    return R, dR


def distortion_jacobian(xy_n: np.ndarray, focal_px: float, k1: float) -> np.ndarray:
    """d uv_px / d x_n of ``uv = f (1 + k1 r^2) x_n + p``.

    Args:
        xy_n: (N, 2) undistorted normalised coordinates.

    Returns:
        (N, 2, 2).
    """
    x, y = xy_n[:, 0], xy_n[:, 1]
    g = 1.0 + k1 * (x * x + y * y)
    out = np.empty((len(xy_n), 2, 2))
    out[:, 0, 0] = g + 2.0 * k1 * x * x
    out[:, 1, 1] = g + 2.0 * k1 * y * y
    out[:, 0, 1] = out[:, 1, 0] = 2.0 * k1 * x * y
    return focal_px * out


def project_state(
    state: np.ndarray, points_w: np.ndarray, width_px: int, height_px: int, want_jacobian: bool = True
) -> tuple[np.ndarray, np.ndarray | None, np.ndarray]:
    """Project world points with the camera state and give d uv / d state.

    Args:
        state: (8,) ``[f, k1, pan, tilt, roll, Cx, Cy, Cz]`` (px, -, rad, rad, rad, m, m, m).
        points_w: (N, 3) metres, pitch frame (z down).
        width_px, height_px: image size; the principal point is its centre.
        want_jacobian: False skips the Jacobian (returned as None).

    Returns:
        uv_px: (N, 2) pixels (NaN-free: points behind the camera get a finite dummy value).
        J: (N, 2, 8) d uv_px / d state, parameter order of ``STATE_NAMES`` (zero rows behind the camera), or None.
        in_front: (N,) bool, False where the camera-frame depth is <= 1e-3 m.
    """
    s = np.asarray(state, dtype=float)
    focal, k1 = s[0], s[1]
    R, dR = rotation_and_derivatives(s[2], s[3], s[4])
    d_w = np.asarray(points_w, dtype=float) - s[5:8]
    points_c = d_w @ R.T
    depth = points_c[:, 2]
    in_front = depth > BEHIND_CAMERA_Z
    safe_depth = np.where(in_front, depth, 1.0)
    xy_n = points_c[:, :2] / safe_depth[:, None]
    r2 = np.einsum("ij,ij->i", xy_n, xy_n)
    g = 1.0 + k1 * r2
    uv_px = focal * g[:, None] * xy_n + np.array([width_px / 2.0, height_px / 2.0])
    if not want_jacobian:
        return uv_px, None, in_front
    J = np.empty((len(points_c), 2, STATE_SIZE))
    J[:, :, 0] = g[:, None] * xy_n
    J[:, :, 1] = focal * r2[:, None] * xy_n
    duv_dXc = _duv_dXc(xy_n, safe_depth, focal, k1)
    dXc_dangles = np.tensordot(d_w, dR, axes=([1], [2])).transpose(0, 2, 1)  # (N, 3, 3): columns pan, tilt, roll
    J[:, :, 2:5] = duv_dXc @ dXc_dangles
    J[:, :, 5:8] = -(duv_dXc @ R)
    J[~in_front] = 0.0
    return uv_px, J, in_front


def _duv_dXc(xy_n: np.ndarray, depth: np.ndarray, focal_px: float, k1: float) -> np.ndarray:
    """(N, 2, 3) d uv_px / d Xc: distortion Jacobian times d x_n / d Xc = (1/z) [[1, 0, -x], [0, 1, -y]]."""
    D = distortion_jacobian(xy_n, focal_px, k1)
    inv_z = 1.0 / depth
    out = np.empty((len(xy_n), 2, 3))
    out[:, :, :2] = D * inv_z[:, None, None]
    out[:, :, 2] = -(D[:, :, 0] * xy_n[:, :1] + D[:, :, 1] * xy_n[:, 1:]) * inv_z[:, None]
    return out


def project_state_dX(state: np.ndarray, points_w: np.ndarray) -> np.ndarray:
    """d uv_px / d X_w (N, 2, 3) for points in front of the camera (see :func:`project_state`)."""
    s = np.asarray(state, dtype=float)
    R, _ = rotation_and_derivatives(s[2], s[3], s[4])
    points_c = (np.asarray(points_w, dtype=float) - s[5:8]) @ R.T
    depth = np.where(points_c[:, 2] > BEHIND_CAMERA_Z, points_c[:, 2], 1.0)
    xy_n = points_c[:, :2] / depth[:, None]
    return _duv_dXc(xy_n, depth, s[0], s[1]) @ R
