"""Image points on the pitch: back-projection of foot points to the ground plane and its uncertainty (numpy only).

A player's foot point (the bottom middle of the box, and its bottom corners) is
back-projected through the frame's camera, distortion included, and intersected with
the ground plane z = 0 (SoccerNet frame: z down, the camera at negative z).

Uncertainty: the ground point X = (x, y) is defined implicitly by ``project(s, X) = uv``
(camera state ``s``, 8-vector of :mod:`broadtrack_graph.geometry.state`). Differentiating,
``J_X dX + J_s ds = duv`` with ``J_X = d uv / d (x, y)`` (2 x 2) and ``J_s = d uv / d s``
(2 x 8), so ``dX/ds = -J_X^-1 J_s`` and ``dX/duv = J_X^-1``; the position covariance is
``A Sigma_s A^T + sigma_px^2 B B^T`` (first order). All points of a frame are handled at once.
The Jacobians use the tracker's distortion model (k1 only); a camera with further
distortion terms (another tool's file) is back-projected with its full model, its
Jacobian taken with k1 alone.
"""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.state import POSITION, STATE_SIZE, project_state

GROUND_OK = "ok"
GROUND_ABOVE_HORIZON = "above the horizon (the ray does not reach the ground in front of the camera)"
GROUND_TOO_FAR = "too far (ground point beyond the distance limit)"
GROUND_OUTSIDE_LENS = "outside the lens model (distortion not invertible there)"
GROUND_NOT_FINITE = "not a finite pixel"

DEFAULT_MAX_DISTANCE_M = 500.0
"""Ground points farther than this from the camera (metres) are rejected: a foot near the horizon."""


def ground_points(camera: Camera, uv_px: np.ndarray, max_distance_m: float = DEFAULT_MAX_DISTANCE_M,
                  roundtrip_tol_px: float = 0.5) -> tuple[np.ndarray, np.ndarray]:
    """Back-project pixels to the ground plane z = 0.

    Args:
        camera: the frame's camera (its resolution is the pixels').
        uv_px: (N, 2) pixels.
        max_distance_m: reject points farther than this from the camera's focal point (metres).
        roundtrip_tol_px: reject points whose re-projection misses the pixel by more (the distortion
            has no inverse there, e.g. beyond the turning radius of a k1 < 0 lens).

    Returns:
        xy_m: (N, 2) ground points, metres, pitch frame; NaN where rejected.
        reasons: (N,) object array of str, :data:`GROUND_OK` or why the point was rejected.
    """
    uv = np.asarray(uv_px, dtype=float).reshape(-1, 2)
    reasons = np.full(len(uv), GROUND_OK, dtype=object)
    xy = np.full((len(uv), 2), np.nan)
    finite = np.isfinite(uv).all(axis=1)
    reasons[~finite] = GROUND_NOT_FINITE
    if not finite.any():
        return xy, reasons
    points, hits = camera.ground_intersection(uv[finite], 0.0)
    index = np.flatnonzero(finite)
    reasons[index[~hits]] = GROUND_ABOVE_HORIZON
    with np.errstate(invalid="ignore"):
        distance = np.linalg.norm(points - camera.position_m, axis=1)
        far = hits & ~(distance <= max_distance_m)
    reasons[index[far]] = GROUND_TOO_FAR
    good = hits & ~far
    if good.any():
        back, in_front = camera.project(points[good])
        miss = ~in_front | ~(np.linalg.norm(back - uv[finite][good], axis=1) <= roundtrip_tol_px)
        bad_index = index[good][miss]
        reasons[bad_index] = GROUND_OUTSIDE_LENS
        good_index = index[good][~miss]
        xy[good_index] = points[good][~miss][:, :2]
    return xy, reasons


def ground_jacobians(state: np.ndarray, xy_m: np.ndarray, width_px: int, height_px: int) -> tuple[np.ndarray, np.ndarray]:
    """Jacobians of ground points with respect to the camera state and to their pixel.

    Args:
        state: (8,) camera state ``[f, k1, pan, tilt, roll, Cx, Cy, Cz]`` (px, -, rad x3, m x3).
        xy_m: (N, 2) ground points (z = 0), metres, finite.
        width_px, height_px: image size of the state's focal length.

    Returns:
        A: (N, 2, 8) d (x, y) / d state (metres per state unit; angles in radians).
        B: (N, 2, 2) d (x, y) / d uv (metres per pixel).
    """
    xy = np.asarray(xy_m, dtype=float).reshape(-1, 2)
    points = np.concatenate([xy, np.zeros((len(xy), 1))], axis=1)
    _, J, _ = project_state(state, points, width_px, height_px)
    # uv depends on X - C, so d uv / d X = -d uv / d C; keep the x and y columns (the point stays at z = 0).
    J_X = -J[:, :, POSITION][:, :, :2]
    B = np.linalg.inv(J_X)
    A = -B @ J
    return A, B


def ground_covariance(state: np.ndarray, xy_m: np.ndarray, width_px: int, height_px: int,
                      state_covariance: np.ndarray, pixel_sigma_px: float) -> np.ndarray:
    """First-order covariance of ground points from the camera's covariance and the pixel noise.

    Args:
        state: (8,) camera state (see :func:`ground_jacobians`).
        xy_m: (N, 2) ground points, metres.
        state_covariance: (8, 8) covariance of the state (units of the state: px, -, rad, m).
        pixel_sigma_px: standard deviation of the foot point in each image axis (pixels).

    Returns:
        (N, 2, 2) covariance of (x, y), square metres.
    """
    A, B = ground_jacobians(state, xy_m, width_px, height_px)
    cov = np.asarray(state_covariance, dtype=float).reshape(STATE_SIZE, STATE_SIZE)
    return A @ cov @ A.transpose(0, 2, 1) + (pixel_sigma_px ** 2) * (B @ B.transpose(0, 2, 1))


def box_feet(boxes_px: np.ndarray) -> np.ndarray:
    """(N, 3, 2) bottom-left, bottom-middle and bottom-right points of boxes (N, 4) [x0, y0, x1, y1] pixels."""
    b = np.asarray(boxes_px, dtype=float).reshape(-1, 4)
    middle = np.column_stack([(b[:, 0] + b[:, 2]) / 2.0, b[:, 3]])
    return np.stack([b[:, [0, 3]], middle, b[:, [2, 3]]], axis=1)


def foot_positions(camera: Camera, boxes_px: np.ndarray, state_covariance: np.ndarray | None,
                   pixel_sigma_px: float = 2.0, max_distance_m: float = DEFAULT_MAX_DISTANCE_M) -> dict:
    """Pitch positions of player boxes: bottom middle (and corners) on the ground, with standard deviations.

    Args:
        camera: the frame's camera (boxes in its pixels).
        boxes_px: (N, 4) [x0, y0, x1, y1] pixels.
        state_covariance: (8, 8) covariance of the camera state (px, -, rad, m), or None (pixel noise only).
        pixel_sigma_px: standard deviation of the foot point per image axis, pixels.
        max_distance_m: ground points farther from the camera are rejected.

    Returns:
        dict with ``xy_m`` (N, 2) bottom middle, ``left_m`` / ``right_m`` (N, 2) bottom corners (metres, NaN
        where they miss the ground), ``std_m`` (N, 2) standard deviations of x and y (metres), ``cov_m2``
        (N, 2, 2), ``reasons`` (N,) :data:`GROUND_OK` or why the middle point has no position.
    """
    feet = box_feet(boxes_px)
    n = len(feet)
    xy_all, reasons_all = ground_points(camera, feet.reshape(-1, 2), max_distance_m)
    xy_all = xy_all.reshape(n, 3, 2)
    reasons = reasons_all.reshape(n, 3)[:, 1]
    xy = xy_all[:, 1]
    cov = np.full((n, 2, 2), np.nan)
    good = np.flatnonzero(reasons == GROUND_OK)
    if len(good):
        covariance = np.zeros((STATE_SIZE, STATE_SIZE)) if state_covariance is None else state_covariance
        cov[good] = ground_covariance(camera.to_vector(), xy[good], camera.width_px, camera.height_px, covariance,
                                      pixel_sigma_px)
    std = np.sqrt(np.clip(np.diagonal(cov, axis1=1, axis2=2), 0.0, None))
    return {"xy_m": xy, "left_m": xy_all[:, 0], "right_m": xy_all[:, 2], "std_m": std, "cov_m2": cov,
            "reasons": reasons}
