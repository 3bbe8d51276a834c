"""Shared by the renderer and the ground truth: surface labels of the label image, projection
that leaves out points a k1 < 0 model folds, and OpenCV fixed-point drawing coordinates.
"""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.camera import Camera

# Surface labels of the label image.
SURFACE_NONE = 0
SURFACE_GROUND = 1
SURFACE_BOARD = 2
SURFACE_STAND = 3
SURFACE_ROOF = 4
SURFACE_GOAL = 5
SURFACE_PLAYER = 6


def project_unfolded(camera: Camera, points_w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Project points; valid (N,) is False behind the camera and where a k1 < 0 model folds.

    With k1 < 0, ``r (1 + k1 r^2)`` turns back beyond ``r^2 = 1 / (3 |k1|)``; points beyond are
    not seen by any pixel (the rays are undistorted on the first branch), so they are not drawn.
    """
    uv, front = camera.project(points_w)
    if camera.k1 >= 0:
        return uv, front
    points_c = camera.world_to_camera(points_w)
    with np.errstate(invalid="ignore", divide="ignore"):
        r2 = (points_c[:, 0] ** 2 + points_c[:, 1] ** 2) / points_c[:, 2] ** 2
    return uv, front & (r2 < 1.0 / (3.0 * -camera.k1))


def fixed_point(uv_px: np.ndarray) -> np.ndarray:
    """(N, 2) pixels -> int32 coordinates with 4 fractional bits for OpenCV drawing (shift=4), clipped far outside."""
    return np.round(np.clip(uv_px, -1e5, 1e5) * 16).astype(np.int32)


def any_near_image(uv: np.ndarray, width: int, height: int, margin: float = 50.0) -> bool:
    """True when a finite point of uv (N, 2) pixels lies within margin pixels of the width x height image."""
    finite = np.isfinite(uv).all(axis=1)
    if not finite.any():
        return False
    u, v = uv[finite, 0], uv[finite, 1]
    return bool(u.max() >= -margin and u.min() < width + margin and v.max() >= -margin and v.min() < height + margin)
