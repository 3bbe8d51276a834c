"""Where the goals are in an image: the region that posts, crossbar and net cover.

A goal is not a ground marking, but its white frame and net are thin bright lines that a
marking detector picks up. Both the naming of detected points and the confidence leave the
goals' region out. Conventions: pitch frame in metres, z down (the crossbar is at z = -2.44).
No I/O.
"""

from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera


def goal_region(camera: Camera, width_px: int, height_px: int, pitch, depth_m: float = 2.5,
                margin_m: float = 0.5) -> np.ndarray | None:
    """(height_px, width_px) bool map of the image covered by the goals (posts, crossbar, net), or None if none.

    Each goal is a box from ``margin_m`` in front of its goal line to ``depth_m`` behind it, the goal's
    width and height plus ``margin_m``; the map is the union of the boxes' projected hulls (a box with a
    corner behind the camera is left out).

    Args:
        camera: any resolution (the map is at width_px x height_px).
        pitch: the template (its dimensions).
    """
    if depth_m <= 0:
        return None
    d = pitch.dimensions
    half_y = d.goal_width_m / 2 + margin_m
    region = None
    scale = width_px / camera.width_px
    for side in (-1.0, 1.0):
        xs = side * np.array([d.length_m / 2 - margin_m, d.length_m / 2 + depth_m])
        corners = np.array([[x, y, z] for x in xs for y in (-half_y, half_y) for z in (margin_m, -d.goal_height_m - margin_m)])
        uv, front = camera.project(corners)
        if not front.all() or not np.isfinite(uv).all():
            continue
        uv = uv * scale
        if (uv[:, 0].max() < 0 or uv[:, 0].min() >= width_px or uv[:, 1].max() < 0 or uv[:, 1].min() >= height_px
                or np.abs(uv).max() > 1e6):
            continue
        if region is None:
            region = np.zeros((height_px, width_px), np.uint8)
        cv2.fillConvexPoly(region, cv2.convexHull(np.round(uv).astype(np.int32)), 1)
    return None if region is None else region.astype(bool)
