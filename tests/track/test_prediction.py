"""The predicted camera (broadtrack_graph.track.prediction): constant motion, hand-computed uncertainty."""

from __future__ import annotations

import math
from collections import deque

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.track.prediction import marking_spread_px, predicted_camera

W, H = 1920, 1080
A = Camera(1000.0, 0.01, 0.10, 1.20, 0.0, (0.0, 50.0, -15.0), W, H)
B = Camera(1010.0, 0.02, 0.11, 1.18, 0.001, (0.1, 50.0, -15.0), W, H)


def test_no_history_no_prediction():
    assert predicted_camera(deque(), None, W) is None


def test_one_camera_is_its_own_prediction_with_three_pixels():
    predicted = predicted_camera(deque([A]), None, W)
    np.testing.assert_array_equal(predicted.camera.to_vector(), A.to_vector())
    assert predicted.uncertainty_px == 3.0


def test_two_cameras_extrapolate_zoom_and_angles_but_hold_k1_and_position():
    predicted = predicted_camera(deque([A, B]), None, W)
    # f +10, pan +0.01, tilt -0.02, roll +0.001; k1 and the focal point as in the last camera.
    np.testing.assert_allclose(predicted.camera.to_vector(), [1020.0, 0.02, 0.12, 1.16, 0.002, 0.1, 50.0, -15.0],
                               rtol=0, atol=1e-12)
    assert (predicted.camera.width_px, predicted.camera.height_px) == (W, H)
    # motion = (0.01 + 0.02) * 1020 + 0.5 * 10 = 35.6 px; uncertainty = 3 + 0.5 * 35.6.
    assert predicted.uncertainty_px == pytest.approx(20.8, abs=1e-9)


def test_marginal_std_adds_to_the_uncertainty():
    std = np.array([2.0, 0.0, 0.001, 0.002, 0.0, 0.0, 0.0, 0.0])
    predicted = predicted_camera(deque([A, B]), std, W)
    # hypot(0.001 * 1020, 0.002 * 1020) + 0.5 * 2 / 1020 * 1920
    assert predicted.uncertainty_px == pytest.approx(20.8 + math.sqrt(1.02**2 + 2.04**2) + 1920 / 1020, abs=1e-9)
    std[3] = np.nan  # a non-finite std is ignored
    assert predicted_camera(deque([A, B]), std, W).uncertainty_px == pytest.approx(20.8, abs=1e-9)


def test_uncertainty_is_capped_at_60_px():
    fast = B.replace(pan_rad=A.pan_rad + 0.2)
    assert predicted_camera(deque([A, fast]), None, W).uncertainty_px == 60.0


def test_an_invalid_extrapolation_falls_back_to_the_last_camera():
    wide, wider = A.replace(focal_px=100.0), A.replace(focal_px=40.0)  # f 100 -> 40 -> -20: not a camera
    predicted = predicted_camera(deque([wide, wider]), None, W)
    assert predicted.camera is wider
    # motion = (0 + 0) * (-20) + 0.5 * 60 = 30 px
    assert predicted.uncertainty_px == pytest.approx(3.0 + 0.5 * 30.0, abs=1e-12)


def test_the_motion_given_replaces_the_difference_of_the_written_cameras():
    # The solver's motion into B (its estimates of A and B as they stand now): a pan of 0.002 rad, nothing else.
    motion = np.array([0.0, 0.5, 0.002, 0.0, 0.0, 3.0, 3.0, 3.0])
    predicted = predicted_camera(deque([A, B]), None, W, motion)
    # k1 and the focal point held; the angles and the zoom moved by the motion.
    np.testing.assert_allclose(predicted.camera.to_vector(), B.to_vector() + [0, 0, 0.002, 0, 0, 0, 0, 0], atol=1e-12)
    assert predicted.uncertainty_px == pytest.approx(3.0 + 0.5 * 0.002 * 1010.0, abs=1e-9)


def _ground_grid() -> np.ndarray:
    x, y = np.meshgrid(np.linspace(-52.5, 52.5, 43), np.linspace(-34.0, 34.0, 29))
    return np.column_stack([x.ravel(), y.ravel(), np.zeros(x.size)])


def test_the_markings_spread_is_the_covariance_carried_into_the_image():
    camera = Camera.from_degrees(2500.0, 0.0, 10.0, 75.0, 0.0, (0.0, 70.0, -12.0), W, H)
    points = _ground_grid()
    # Pan alone uncertain by 1 mrad: every point moves by its pan derivative times 1 mrad, as the pan turned by it.
    sigma = 1e-3
    covariance = np.zeros((8, 8))
    covariance[2, 2] = sigma**2
    turned = camera.replace(pan_rad=camera.pan_rad + sigma)
    uv, front = camera.project(points)
    uv_turned, _ = turned.project(points)
    seen = front & camera.in_image(uv)
    moved = np.percentile(np.hypot(*(uv_turned[seen] - uv[seen]).T), 90)
    assert marking_spread_px(camera, covariance, points) == pytest.approx(moved, rel=0.01)
    # Pan against a sideways step of the focal point that moves the middle of the view the same: each alone moves
    # the markings by about f * 1 mrad, together (fully correlated) the view's markings move far less.
    depth = np.linalg.norm(camera.ground_intersection(np.array([[W / 2, H / 2]]))[0][0] - camera.position_m)
    step = np.zeros(8)
    step[2] = sigma
    step[5:8] = sigma * depth * np.array([np.cos(camera.pan_rad), np.sin(camera.pan_rad), 0.0])
    for sign in (1.0, -1.0):
        step[5:8] *= sign
        together = marking_spread_px(camera, np.outer(step, step), points)
        apart = marking_spread_px(camera, np.diag(step**2), points)
        if together < apart:
            break
    assert together < 0.5 * apart
    # With the covariance, the prediction's uncertainty is 3 px plus that spread.
    predicted = predicted_camera(deque([camera]), np.sqrt(np.diag(covariance)), W, None, covariance, points)
    assert predicted.uncertainty_px == pytest.approx(3.0 + moved, rel=0.01)


def test_a_view_with_no_template_point_falls_back_on_the_deviations():
    sky = Camera.from_degrees(2500.0, 0.0, 10.0, 150.0, 0.0, (0.0, 70.0, -12.0), W, H)  # looking up
    covariance = np.diag([4.0, 0, 1e-6, 1e-6, 0, 0, 0, 0])
    assert marking_spread_px(sky, covariance, _ground_grid()) is None
    std = np.sqrt(np.diag(covariance))
    with_covariance = predicted_camera(deque([sky]), std, W, None, covariance, _ground_grid())
    assert with_covariance.uncertainty_px == pytest.approx(predicted_camera(deque([sky]), std, W).uncertainty_px)
