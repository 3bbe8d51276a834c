"""Re-initialisation from keypoints: focal length from a ray angle, the two-point method, RANSAC over pairs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.keypoints import (
    camera_from_two_points,
    focal_from_ray_angle,
    reinit_from_keypoints,
)

W, H = 960, 540
PITCH = PitchTemplate()


def _camera(pan=-12.0, tilt=76.0, focal=1100.0, k1=0.0, position=(1.5, 57.0, -13.0), roll=0.3):
    return Camera.from_degrees(focal, k1, pan, tilt, roll, position, W, H)


def test_focal_from_ray_angle_inverts_the_angle():
    uv = np.array([[100.0, 200.0], [800.0, 350.0]])
    for focal in (500.0, 1500.0, 4000.0):
        a = np.array([uv[0, 0] - W / 2, uv[0, 1] - H / 2, focal])
        b = np.array([uv[1, 0] - W / 2, uv[1, 1] - H / 2, focal])
        angle = math.acos(a @ b / np.linalg.norm(a) / np.linalg.norm(b))
        assert focal_from_ray_angle(uv, angle, W, H) == pytest.approx(focal, rel=1e-6)
    assert focal_from_ray_angle(uv, math.radians(179), W, H) is None


def test_two_point_method_recovers_a_roll_free_camera():
    truth = _camera(roll=0.0, position=(0.0, 55.0, -12.0))
    points_w = np.array([[-20.0, 10.0, 0.0], [15.0, -20.0, 0.0]])
    uv, _ = truth.project(points_w)
    camera = camera_from_two_points(uv, points_w, truth.position_m, W, H)
    assert camera.focal_px == pytest.approx(truth.focal_px, rel=1e-3)
    assert camera.pan_deg == pytest.approx(truth.pan_deg, abs=0.05)
    assert camera.tilt_deg == pytest.approx(truth.tilt_deg, abs=0.05)
    assert camera.roll_rad == 0.0
    assert camera_from_two_points(uv[[0, 0]], points_w[[0, 0]], truth.position_m, W, H) is None


def test_reinit_from_keypoints_ransac_rejects_outliers():
    truth = _camera(roll=0.0, position=(0.0, 55.0, -12.0))
    names = [n for n in PITCH.keypoints if PITCH.is_on_ground(n.split(" | ")[0].split(" (")[0])]
    pts = PITCH.keypoint_array(names)
    uv, front = truth.project(pts)
    ok = front & truth.in_image(uv)
    uv, pts = uv[ok], pts[ok]
    assert len(uv) >= 5
    rng = np.random.default_rng(3)
    uv_noisy = uv + rng.normal(0, 0.5, uv.shape)
    uv_noisy[:2] += 150.0  # two gross outliers
    result = reinit_from_keypoints(uv_noisy, pts, W, H)
    assert result.camera is not None
    assert result.camera.pan_deg == pytest.approx(truth.pan_deg, abs=0.3)
    assert result.camera.focal_px == pytest.approx(truth.focal_px, rel=0.03)
    assert result.score.inlier_share == pytest.approx((len(uv) - 2) / len(uv))
