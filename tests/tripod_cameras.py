"""Synthetic cameras on a known tripod, for the tripod tests of the track package."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.camera import Camera, rotation_from_angles
from broadtrack_graph.geometry.tripod import Tripod, focal_point


def cameras_on(tripod: Tripod, count: int, seed: int = 1) -> list[Camera]:
    """Cameras on the tripod; lambda = 0.2 m (the provisional tripod's assumption), wide pan and tilt."""
    rng = np.random.default_rng(seed)
    cameras = []
    for _ in range(count):
        pan, tilt = np.radians(rng.uniform(-40, 40)), np.radians(rng.uniform(60, 85))
        R = rotation_from_angles(pan, tilt, 0.0)
        cameras.append(Camera(2000.0, 0.0, pan, tilt, 0.0, focal_point(R, tripod, 0.2), 1920, 1080))
    return cameras
