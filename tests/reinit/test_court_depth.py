"""Cameras along a camera's line of sight: the point looked at stays put, its surroundings keep their size."""

from __future__ import annotations

import math

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.reinit.court_depth import along_line_of_sight

W, H = 1280, 720


def _camera(position, pan_deg=20.0, tilt_deg=75.0) -> Camera:
    return Camera(3000.0, 0.01, math.radians(pan_deg), math.radians(tilt_deg), 0.01, np.asarray(position, float), W, H)


def test_the_ground_point_looked_at_stays_at_the_image_centre_and_its_surroundings_keep_their_size():
    camera = _camera((-10.0, 60.0, -20.0))
    axis = camera.optical_axis_w
    look_at = camera.position_m + (-camera.position_m[2] / axis[2]) * axis
    near = look_at + np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    uv0, _ = camera.project(near)
    moved = along_line_of_sight(camera, [0.5, 1.0, 2.0])
    assert len(moved) == 3
    for factor, other in zip([0.5, 1.0, 2.0], moved):
        uv, ok = other.project(near)
        assert ok.all()
        np.testing.assert_allclose(uv[0], camera.principal_point, atol=1e-6)
        # a metre on the ground beside it: the same length in the image within a few per cent (perspective changes)
        np.testing.assert_allclose(np.linalg.norm(uv[1:] - uv[:1], axis=1), np.linalg.norm(uv0[1:] - uv0[:1], axis=1),
                                   rtol=0.05)
        np.testing.assert_allclose(other.focal_px, factor * camera.focal_px)
        np.testing.assert_allclose(np.linalg.norm(other.position_m - look_at),
                                   factor * np.linalg.norm(camera.position_m - look_at))
        assert (other.pan_rad, other.tilt_rad, other.roll_rad, other.k1) == \
            (camera.pan_rad, camera.tilt_rad, camera.roll_rad, camera.k1)


def test_a_view_above_the_horizon_has_no_line_of_sight_to_walk():
    assert along_line_of_sight(_camera((0.0, 60.0, -20.0), tilt_deg=95.0), [0.5, 2.0]) == []
