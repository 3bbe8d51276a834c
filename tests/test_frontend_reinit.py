"""Re-initialisation: two-point method, homography decomposition, search + fit, keypoint RANSAC, line fitting."""

from __future__ import annotations

import math

import numpy as np
import pytest

from broadtrack_graph.camera import Camera
from broadtrack_graph.evaluate import TemplateSampling
from broadtrack_graph.frontend.linefit import LineFitConfig, TemplateCurves, fit_camera_to_lines
from broadtrack_graph.frontend.reinit import (
    camera_from_homography, camera_from_two_points, focal_from_ray_angle, homography_from_lines,
    reinit_from_keypoints, reinit_from_lines, score_labelled,
)
from broadtrack_graph.pitch import PitchTemplate

W, H = 960, 540
PITCH = PitchTemplate()
CURVES = TemplateCurves(PITCH)
SAMPLING = TemplateSampling(PITCH)


def _camera(pan=-12.0, tilt=76.0, focal=1100.0, k1=0.0, position=(1.5, 57.0, -13.0), roll=0.3):
    return Camera.from_degrees(focal, k1, pan, tilt, roll, position, W, H)


def _lines(camera, rng=None, noise_px=0.0, per_class=12):
    """Visible template classes as labelled points (like an annotation)."""
    out = {}
    for name, pts in PITCH.sample_uniform(0.5).items():
        uv, front = camera.project(pts)
        ok = front & camera.in_image(uv)
        if ok.sum() < 4:
            continue
        sel = uv[ok][np.linspace(0, ok.sum() - 1, per_class).astype(int)]
        if rng is not None:
            sel = sel + rng.normal(0, noise_px, sel.shape)
        out[name] = sel
    return out


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


def test_homography_decomposition_recovers_the_camera():
    truth = _camera(k1=0.0)
    lines = _lines(truth)
    Hmat = homography_from_lines(lines, PITCH)
    assert Hmat is not None
    camera = camera_from_homography(Hmat, W, H)
    assert camera.focal_px == pytest.approx(truth.focal_px, rel=0.01)
    np.testing.assert_allclose(camera.position_m, truth.position_m, atol=0.3)
    assert camera.pan_deg == pytest.approx(truth.pan_deg, abs=0.1)
    assert homography_from_lines({k: v for k, v in list(lines.items())[:2]}, PITCH) is None


def test_fit_camera_to_lines_converges_from_a_perturbed_start():
    truth = _camera(k1=0.04)
    lines = _lines(truth, np.random.default_rng(1), noise_px=0.3)
    start = truth.replace(pan_rad=truth.pan_rad + 0.02, tilt_rad=truth.tilt_rad - 0.01, focal_px=truth.focal_px * 1.08,
                          k1=0.0)
    result = fit_camera_to_lines(start, lines, CURVES, LineFitConfig())
    assert 0.0 < result.max_distance_px < 1.5
    assert result.camera.focal_px == pytest.approx(truth.focal_px, rel=0.03)
    assert result.camera.pan_deg == pytest.approx(truth.pan_deg, abs=0.2)


@pytest.mark.parametrize("case", [
    dict(pan=-12.0, tilt=76.0, focal=1100.0, position=(1.5, 57.0, -13.0)),  # wide, many lines
    dict(pan=28.0, tilt=74.0, focal=1900.0, position=(-2.0, 60.0, -15.0)),  # right penalty area
])
def test_reinit_from_lines_reaches_every_class(case):
    truth = _camera(**case)
    lines = _lines(truth, np.random.default_rng(2), noise_px=0.5)
    result = reinit_from_lines(lines, W, H, PITCH, curves=CURVES, sampling=SAMPLING)
    assert result.camera is not None
    score = score_labelled(result.camera, lines, 5.0, SAMPLING)
    assert score.fn == 0 and score.inlier_share == 1.0
    np.testing.assert_allclose(result.camera.position_m, truth.position_m, atol=3.0)


def test_reinit_from_lines_without_usable_class_is_none():
    result = reinit_from_lines({"Line unknown": np.zeros((3, 2))}, W, H, PITCH, curves=CURVES, sampling=SAMPLING)
    assert result.camera is None and result.reason


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
