"""Where a camera looks on the ground, and cameras aimed at a ground point. No I/O.

Conventions: pitch frame in metres, origin at the centre spot, z down (the ground is z = 0, a camera above it has
z < 0); rotation ``R = (Rz(pan) Rx(tilt) Rz(roll))^T`` (:mod:`broadtrack_graph.geometry.camera`).
"""

from __future__ import annotations

import math

import numpy as np

from broadtrack_graph.geometry.camera import Camera


def aim_angles(T_w: np.ndarray, aim_w: np.ndarray) -> tuple[float, float]:
    """Pan and tilt (radians) whose optical axis from T_w passes through the ground point aim_w (3,)."""
    direction = np.asarray(aim_w, float) - np.asarray(T_w, float)
    direction /= np.linalg.norm(direction)
    return math.atan2(direction[0], -direction[1]), math.acos(float(np.clip(direction[2], -1.0, 1.0)))


def ground_aim(camera: Camera) -> np.ndarray | None:
    """(3,) the ground point (z = 0) the camera's optical axis passes through, metres; None when the axis does not
    reach the ground in front of the camera (it looks level or up, or the focal point is not above the ground)."""
    axis, position = camera.optical_axis_w, camera.position_m
    if axis[2] <= 1e-9 or position[2] >= 0.0:
        return None
    return position + (-position[2] / axis[2]) * axis


def moved_keeping_view(camera: Camera, position_w: np.ndarray) -> Camera | None:
    """The camera moved to ``position_w`` with the view of the ground where it looks kept: its optical axis through
    the same ground point (:func:`ground_aim`) and its focal length scaled by the two distances to that point (the
    same image scale there), roll and lens kept. A narrow view is nearly the same image from anywhere along its line of
    sight this way; a wide view's perspective shows the move. None when the camera does not look at the ground or
    ``position_w`` is not above it.

    Args:
        position_w: (3,) metres, pitch frame (z down).
    """
    aim = ground_aim(camera)
    position = np.asarray(position_w, float).reshape(3)
    if aim is None or position[2] >= 0.0:
        return None
    pan, tilt = aim_angles(position, aim)
    scale = float(np.linalg.norm(aim - position) / np.linalg.norm(aim - camera.position_m))
    return camera.replace(position_m=position, pan_rad=pan, tilt_rad=tilt, focal_px=camera.focal_px * scale)
