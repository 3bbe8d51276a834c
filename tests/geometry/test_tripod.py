"""The tripod model's helpers (broadtrack_graph.geometry.tripod): how far the image moves between two cameras."""

from __future__ import annotations

import math

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.tripod import image_motion_px, image_motion_vector

W, H = 1920, 1080


def _camera(focal_px: float = 2000.0, pan_deg: float = 0.0, tilt_deg: float = 75.0) -> Camera:
    return Camera.from_degrees(focal_px, 0.0, pan_deg, tilt_deg, 0.0, (0.0, 55.0, -12.0), W, H)


def _moved_px(previous: Camera, camera: Camera, image_point) -> float:
    """How far the ground point seen at image_point by ``previous`` moves in the image, at 960 wide."""
    ray = previous.R_cw.T @ np.array([(image_point[0] - W / 2) / previous.focal_px,
                                      (image_point[1] - H / 2) / previous.focal_px, 1.0])
    ground = previous.position_m + ray * (-previous.position_m[2] / ray[2])
    (before,), _ = previous.project(ground[None])
    (after,), _ = camera.project(ground[None])
    return float(np.linalg.norm(after - before)) * 960 / W


def test_a_pan_moves_the_image_centre_by_the_turn_times_the_focal_length():
    previous, camera = _camera(), _camera(pan_deg=1.0)
    assert image_motion_px(previous, previous) == 0.0
    turn = math.acos(previous.R_cw[2] @ camera.R_cw[2])  # under 1 deg: the axis is tilted down from the horizon
    assert turn < math.radians(1.0)
    assert image_motion_px(previous, camera) == pytest.approx(turn * 2000.0 * 960 / W, rel=1e-6)
    assert image_motion_px(previous, camera) == pytest.approx(_moved_px(previous, camera, (W / 2, H / 2)), rel=0.05)


def test_a_zoom_moves_the_image_side_edges_and_both_ways_alike():
    previous, camera = _camera(), _camera(focal_px=2200.0)
    assert image_motion_px(previous, camera) == pytest.approx(_moved_px(previous, camera, (0.0, H / 2)), rel=0.06)
    assert image_motion_px(camera, previous) == pytest.approx(image_motion_px(previous, camera))


def test_the_image_motion_vector_points_where_the_image_moves():
    previous = _camera()
    still = image_motion_vector(previous, previous)
    np.testing.assert_allclose(still, [0.0, 0.0], atol=1e-6)
    # A pan moves the image sideways, by about the turn times the focal length (image_motion_px's measure).
    panned = _camera(pan_deg=1.0)
    motion = image_motion_vector(previous, panned)
    assert abs(motion[0]) > 20.0 * abs(motion[1])
    assert np.hypot(*motion) * 960 / W == pytest.approx(image_motion_px(previous, panned), rel=0.02)
    # The other way round, the other way; a tilt moves it up or down.
    np.testing.assert_allclose(image_motion_vector(panned, previous), -motion, rtol=0.02, atol=0.5)
    tilted = image_motion_vector(previous, _camera(tilt_deg=76.0))
    assert abs(tilted[1]) > 20.0 * abs(tilted[0])
