"""The predicted camera of the next frame (for the detector's labelling gate): constant motion, and how far its
projected markings may be off."""

from __future__ import annotations

import math
from collections import deque

import numpy as np

from broadtrack_graph.detect.detector import PredictedCamera
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.state import project_state

SPREAD_PERCENTILE = 90.0
"""The markings' image spread of a camera is this percentile of its visible template points' spreads."""
MIN_SPREAD_POINTS = 10
"""Fewer template points in view: the spread is read from the angles' and the focal length's deviations instead."""


def marking_spread_px(camera: Camera, covariance: np.ndarray, points_w: np.ndarray) -> float | None:
    """How far (pixels, 1 sigma) a camera's projected markings may be off, from its state's covariance.

    Each template point in view moves by ``J d`` for a state error ``d`` (``J``: its (2, 8) projection Jacobian), so
    its image covariance is ``J C J^T``; its spread is the root of that covariance's larger eigenvalue, and the
    camera's is :data:`SPREAD_PERCENTILE` of its points'. Parameters that trade against each other (focal length
    against distance, pan against a sideways step of the focal point: a narrow or grazing view barely tells them
    apart) are each uncertain while the markings they move together are not: their deviations alone would overstate
    the markings' by several times.

    Args:
        camera: the camera; covariance: (8, 8) of its state (state order); points_w: (N, 3) template points, metres.

    Returns:
        pixels, or None with under :data:`MIN_SPREAD_POINTS` points in view.
    """
    uv, J, front = project_state(camera.to_vector(), points_w, camera.width_px, camera.height_px)
    seen = front & camera.in_image(uv)
    if np.count_nonzero(seen) < MIN_SPREAD_POINTS:
        return None
    J = J[seen]
    image_cov = np.einsum("nik,kl,njl->nij", J, np.asarray(covariance, float), J)  # (n, 2, 2)
    a, b, c = image_cov[:, 0, 0], image_cov[:, 0, 1], image_cov[:, 1, 1]
    largest = 0.5 * (a + c) + np.sqrt(np.maximum(0.25 * (a - c) ** 2 + b * b, 0.0))
    return float(np.percentile(np.sqrt(np.maximum(largest, 0.0)), SPREAD_PERCENTILE))


def predicted_camera(history: deque, std: np.ndarray | None, width_px: int,
                     motion: np.ndarray | None = None, covariance: np.ndarray | None = None,
                     points_w: np.ndarray | None = None) -> PredictedCamera | None:
    """The previous camera moved by the last inter-frame motion, with a pixel uncertainty.

    The motion is the change of focal length, pan, tilt and roll into the last camera (k1 and the focal point are
    held): ``motion`` when given (the solver's, between its current estimates of the last two frames), else the
    difference of the last two cameras as they were written (a chain that moved as a whole on the last frame moved
    the last camera but not the one before: that is no motion of the camera). The uncertainty (pixels, 1 sigma, at most
    60) is ``3 + 0.5 * motion`` with ``motion = (|d pan| + |d tilt|) * f + 0.5 * |d f|``,
    plus the last camera's markings' spread (:func:`marking_spread_px`) with its covariance and template points, else,
    with finite marginal standard deviations, ``hypot(std_pan * f, std_tilt * f) + 0.5 * std_f / max(f, 1) *
    width_px`` (f: the predicted focal length).

    Args:
        history: the last one or two trusted cameras, oldest first (empty: no prediction).
        motion: (8,) state change into the last camera (state order), or None.
        std: (8,) marginal standard deviations of the last camera in state order, or None.
        covariance: (8, 8) the last camera's state covariance, or None; points_w: (N, 3) the template's points on
            the ground, metres (both or neither).
        width_px: image width in pixels.

    Returns:
        PredictedCamera (camera at the last camera's resolution), or None without history.
        When the moved state is not a valid camera, the last camera itself.
    """
    if not history:
        return None
    last = history[-1]
    state = last.to_vector()
    motion_px = 0.0
    if motion is not None or len(history) >= 2:
        velocity = np.array(motion, float) if motion is not None else state - history[-2].to_vector()
        velocity[1] = 0.0
        velocity[5:] = 0.0
        state = state + velocity
        motion_px = abs(velocity[2]) * state[0] + abs(velocity[3]) * state[0] + abs(velocity[0]) * 0.5
    uncertainty = 3.0 + 0.5 * motion_px
    spread = None
    if covariance is not None and points_w is not None and np.all(np.isfinite(covariance)):
        spread = marking_spread_px(last, covariance, points_w)
    if spread is not None:
        uncertainty += spread
    elif std is not None and np.all(np.isfinite(std)):
        uncertainty += math.hypot(std[2] * state[0], std[3] * state[0]) + 0.5 * std[0] / max(state[0], 1.0) * width_px
    try:
        camera = Camera.from_vector(state, last.width_px, last.height_px)
    except ValueError:
        camera = last
    return PredictedCamera(camera, float(min(uncertainty, 60.0)))
