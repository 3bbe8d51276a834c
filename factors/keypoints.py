"""Keypoint factor: labelled image points to their known 3D pitch points.

Residual per keypoint: ``(project(X_k) - uv_k) sqrt(conf_k) / sigma_px`` (2 values),
per-point Cauchy loss on its norm. Points behind the camera get a constant residual.
"""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.state import STATE_SIZE, project_state
from factors.custom import Residuals, custom_factor
from factors.robust import INVALID_RESIDUAL_SIGMAS, cauchy_rows

MIN_CONFIDENCE = 0.05


def keypoint_residuals(
    state: np.ndarray, uv_px: np.ndarray, points_w: np.ndarray, width_px: int, height_px: int, want_jacobian: bool = True
):
    """Reprojection errors of keypoints.

    Args:
        state: (8,) camera state.
        uv_px: (N, 2) observed pixels; points_w: (N, 3) metres.

    Returns:
        :class:`~factors.custom.Residuals`: residual (N, 2) projected minus observed, pixels;
        jacobians [(N, 2, 8)] or None; valid (N,) bool (in front of the camera).
    """
    uv_hat, J, in_front = project_state(state, points_w, width_px, height_px, want_jacobian)
    residual = np.where(in_front[:, None], uv_hat - uv_px, 0.0)
    return Residuals(residual, None if J is None else [J], in_front)


def make_keypoint_factor(key, uv_px, points_w, confidence, width_px, height_px, sigma_px, cauchy_scale):
    """CustomFactor on one camera state: all keypoints of a frame (residual length 2N)."""
    uv_px = np.ascontiguousarray(uv_px, dtype=float)
    points_w = np.ascontiguousarray(points_w, dtype=float)
    weight = np.sqrt(np.clip(np.asarray(confidence, dtype=float), MIN_CONFIDENCE, 1.0)) / sigma_px
    count = len(uv_px)

    def fn(vectors, want_jacobian):
        r, Js, valid = keypoint_residuals(vectors[0], uv_px, points_w, width_px, height_px, want_jacobian)
        r = np.where(valid[:, None], r * weight[:, None], INVALID_RESIDUAL_SIGMAS / np.sqrt(2.0))
        Js = None if Js is None else [Js[0] * weight[:, None, None]]
        r, Js = cauchy_rows(r, Js, cauchy_scale)
        return r.reshape(-1), None if Js is None else [Js[0].reshape(2 * count, STATE_SIZE)]

    return custom_factor([key], [STATE_SIZE], 2 * count, fn)
