"""The predicted camera of the next frame (for the detector's labelling gate): constant motion."""

from __future__ import annotations

import math
from collections import deque

import numpy as np

from broadtrack_graph.detect.detector import PredictedCamera
from broadtrack_graph.geometry.camera import Camera


def predicted_camera(history: deque, std: np.ndarray | None, width_px: int) -> PredictedCamera | None:
    """The previous camera moved by the last inter-frame motion, with a pixel uncertainty.

    The motion is the change of focal length, pan, tilt and roll between the last two
    cameras (k1 and the focal point are held). The uncertainty (pixels, 1 sigma, at most
    60) is ``3 + 0.5 * motion`` with ``motion = (|d pan| + |d tilt|) * f + 0.5 * |d f|``,
    plus, with finite marginal standard deviations, ``hypot(std_pan * f, std_tilt * f)
    + 0.5 * std_f / max(f, 1) * width_px`` (f: the predicted focal length).

    Args:
        history: the last one or two trusted cameras, oldest first (empty: no prediction).
        std: (8,) marginal standard deviations of the last camera in state order, or None.
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
    if len(history) >= 2:
        velocity = state - history[-2].to_vector()
        velocity[1] = 0.0
        velocity[5:] = 0.0
        state = state + velocity
        motion_px = abs(velocity[2]) * state[0] + abs(velocity[3]) * state[0] + abs(velocity[0]) * 0.5
    uncertainty = 3.0 + 0.5 * motion_px
    if std is not None and np.all(np.isfinite(std)):
        uncertainty += math.hypot(std[2] * state[0], std[3] * state[0]) + 0.5 * std[0] / max(state[0], 1.0) * width_px
    try:
        camera = Camera.from_vector(state, last.width_px, last.height_px)
    except ValueError:
        camera = last
    return PredictedCamera(camera, float(min(uncertainty, 60.0)))
