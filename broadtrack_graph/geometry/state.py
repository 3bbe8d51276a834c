"""The tracker's 8-vector camera state, its projection and analytic Jacobian (numpy only, no I/O).

State ``s = [f, k1, pan, tilt, roll, Cx, Cy, Cz]`` (pixels, unitless, radians x3,
metres x3; the order of :data:`STATE_NAMES`), SoccerNet convention: world frame with
z down, ``R_cw = (Rz(pan) Rx(tilt) Rz(roll))^T`` with
``Rz(a) = [[c,-s,0],[s,c,0],[0,0,1]]`` and ``Rx(t) = [[1,0,0],[0,c,-s],[0,s,c]]``,
``Xc = R_cw (X_w - C_w)``, ``x_n = Xc_xy / Xc_z``, ``uv = f (1 + k1 r^2) x_n + p`` with
``p = (W / 2, H / 2)``. :class:`broadtrack_graph.geometry.camera.Camera` converts to and
from this vector and uses the same rotation builders.
"""

from __future__ import annotations

import math

import numpy as np

from broadtrack_graph.geometry.distortion import unfolded_radius2

STATE_NAMES: tuple[str, ...] = ("f_px", "k1", "pan_rad", "tilt_rad", "roll_rad", "Cx_m", "Cy_m", "Cz_m")
"""Parameter order of the camera state (columns of every camera Jacobian), each name ending in its unit."""

STATE_SIZE = len(STATE_NAMES)
"""Length of the camera state vector (8)."""

FOCAL = 0
"""Index of f (pixels at the image size the state refers to)."""
K1 = 1
"""Index of k1 (radial distortion, normalised coordinates)."""
PAN, TILT, ROLL = 2, 3, 4
"""Indices of pan, tilt, roll (radians)."""
ANGLES = slice(PAN, ROLL + 1)
"""Slice of (pan, tilt, roll) in the state."""
POSITION = slice(5, 8)
"""Slice of the focal point (Cx, Cy, Cz), metres, pitch frame (z down)."""

BEHIND_CAMERA_Z = 1e-3
"""Camera-frame depth (metres) at or below which a point counts as behind the camera."""


# --------------------------------------------------------------------------- rotation builders


def rotation_z(angle_rad: float) -> np.ndarray:
    """(3, 3) ``Rz(a) = [[c, -s, 0], [s, c, 0], [0, 0, 1]]``."""
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rotation_x(angle_rad: float) -> np.ndarray:
    """(3, 3) ``Rx(a) = [[1, 0, 0], [0, c, -s], [0, s, c]]``."""
    c, s = math.cos(angle_rad), math.sin(angle_rad)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


def _rotation_factors(pan_rad: float, tilt_rad: float, roll_rad: float) -> np.ndarray:
    """(6, 3, 3) ``Rz(pan), dRz(pan), Rx(tilt), dRx(tilt), Rz(roll), dRz(roll)`` built in one array (the numbers of
    :func:`rotation_z`, :func:`rotation_x` and their derivatives)."""
    cp, sp = math.cos(pan_rad), math.sin(pan_rad)
    ct, st = math.cos(tilt_rad), math.sin(tilt_rad)
    cr, sr = math.cos(roll_rad), math.sin(roll_rad)
    return np.array([[[cp, -sp, 0.0], [sp, cp, 0.0], [0.0, 0.0, 1.0]],
                     [[-sp, -cp, 0.0], [cp, -sp, 0.0], [0.0, 0.0, 0.0]],
                     [[1.0, 0.0, 0.0], [0.0, ct, -st], [0.0, st, ct]],
                     [[0.0, 0.0, 0.0], [0.0, -st, -ct], [0.0, ct, -st]],
                     [[cr, -sr, 0.0], [sr, cr, 0.0], [0.0, 0.0, 1.0]],
                     [[-sr, -cr, 0.0], [cr, -sr, 0.0], [0.0, 0.0, 0.0]]])


def rotation_from_angles(pan_rad: float, tilt_rad: float, roll_rad: float) -> np.ndarray:
    """World-to-camera rotation ``R_cw = (Rz(pan) Rx(tilt) Rz(roll))^T``.

    Args:
        pan_rad, tilt_rad, roll_rad: angles in radians (SoccerNet convention).

    Returns:
        (3, 3) rotation matrix mapping world vectors to camera vectors.
    """
    return (rotation_z(pan_rad) @ rotation_x(tilt_rad) @ rotation_z(roll_rad)).T


def rotation_and_derivatives(pan_rad: float, tilt_rad: float, roll_rad: float) -> tuple[np.ndarray, np.ndarray]:
    """World-to-camera rotation and its derivatives with respect to pan, tilt, roll.

    Args:
        pan_rad, tilt_rad, roll_rad: angles in radians.

    Returns:
        R_cw: (3, 3) ``(Rz(pan) Rx(tilt) Rz(roll))^T``.
        dR: (3, 3, 3), ``dR[i]`` = d R_cw / d angle_i for angles (pan, tilt, roll).
    """
    P, dP, T, dT, Q, dQ = _rotation_factors(pan_rad, tilt_rad, roll_rad)
    PT = P @ T
    return (PT @ Q).T, np.stack([(dP @ T @ Q).T, (P @ dT @ Q).T, (PT @ dQ).T])


def angles_from_rotations(R_cw: np.ndarray) -> np.ndarray:
    """Pan, tilt and roll (radians) of many world-to-camera rotations at once:
    :func:`~broadtrack_graph.geometry.camera.angles_from_rotation`'s rule in numpy (numpy's arctan2 and hypot can
    differ from :mod:`math`'s in the last bit, so the single-matrix function keeps its own scalar arithmetic, whose
    numbers the homography decomposition's cameras rest on).

    Two (pan, tilt, roll) triples give the same matrix (tilt and -tilt); the one
    whose roll is nearest 0 is returned, as camera operators keep roll small.
    At tilt 0 or 180 deg only pan + roll is defined; roll is then set to 0.

    Args:
        R_cw: (N, 3, 3) rotation matrices, world to camera.

    Returns:
        (N, 3) ``[pan_rad, tilt_rad, roll_rad]``.
    """
    orientation = np.swapaxes(np.asarray(R_cw, dtype=float).reshape(-1, 3, 3), 1, 2)  # Rz(pan) Rx(tilt) Rz(roll)
    cos_tilt = np.clip(orientation[:, 2, 2], -1.0, 1.0)
    sin_tilt_abs = np.hypot(orientation[:, 2, 0], orientation[:, 2, 1])
    triples = []
    for sign in (1.0, -1.0):
        triples.append(np.stack([np.arctan2(sign * orientation[:, 0, 2], -sign * orientation[:, 1, 2]),
                                 np.arctan2(sign * sin_tilt_abs, cos_tilt),
                                 np.arctan2(sign * orientation[:, 2, 0], sign * orientation[:, 2, 1])], axis=1))
    angles = np.where((np.abs(triples[1][:, 2]) < np.abs(triples[0][:, 2]))[:, None], triples[1], triples[0])
    # Gimbal lock: orientation = Rz(pan +- roll); choose roll = 0.
    locked = sin_tilt_abs < 1e-12
    angles[locked] = np.stack([np.arctan2(orientation[locked, 1, 0], orientation[locked, 0, 0]),
                               np.where(cos_tilt[locked] > 0, 0.0, np.pi), np.zeros(locked.sum())], axis=1)
    return angles


# --------------------------------------------------------------------------- projection


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
        in_front: (N,) bool, False where the camera-frame depth is <= 1e-3 m or the point lies beyond the
            radius where the distortion folds back (:func:`~broadtrack_graph.geometry.distortion.unfolded_radius2`).
    """
    s = np.asarray(state, dtype=float)
    focal, k1 = s[FOCAL], s[K1]
    if want_jacobian:
        R, dR = rotation_and_derivatives(s[PAN], s[TILT], s[ROLL])
    else:
        R = rotation_from_angles(s[PAN], s[TILT], s[ROLL])
    d_w = np.asarray(points_w, dtype=float) - s[POSITION]
    points_c = d_w @ R.T
    depth = points_c[:, 2]
    in_front = depth > BEHIND_CAMERA_Z
    safe_depth = np.where(in_front, depth, 1.0)
    xy_n = points_c[:, :2] / safe_depth[:, None]
    r2 = np.einsum("ij,ij->i", xy_n, xy_n)
    in_front &= r2 < unfolded_radius2(k1)
    g = 1.0 + k1 * r2
    uv_px = focal * g[:, None] * xy_n + np.array([width_px / 2.0, height_px / 2.0])
    if not want_jacobian:
        return uv_px, None, in_front
    J = np.empty((len(points_c), 2, STATE_SIZE))
    J[:, :, FOCAL] = g[:, None] * xy_n
    J[:, :, K1] = focal * r2[:, None] * xy_n
    duv_dXc = _duv_dXc(xy_n, safe_depth, focal, k1)
    # (N, 3, 3) d Xc / d (pan, tilt, roll), columns pan, tilt, roll: d_w contracted with dR's last axis (one product)
    dXc_dangles = np.dot(d_w, dR.transpose(2, 0, 1).reshape(3, 9)).reshape(-1, 3, 3).transpose(0, 2, 1)
    J[:, :, ANGLES] = duv_dXc @ dXc_dangles
    J[:, :, POSITION] = -(duv_dXc @ R)
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
    R, _ = rotation_and_derivatives(s[PAN], s[TILT], s[ROLL])
    points_c = (np.asarray(points_w, dtype=float) - s[POSITION]) @ R.T
    depth = np.where(points_c[:, 2] > BEHIND_CAMERA_Z, points_c[:, 2], 1.0)
    xy_n = points_c[:, :2] / depth[:, None]
    return _duv_dXc(xy_n, depth, s[FOCAL], s[K1]) @ R
