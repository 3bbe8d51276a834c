"""The predicted camera (broadtrack_graph.track.prediction): constant motion, hand-computed uncertainty."""

from __future__ import annotations

import math
from collections import deque

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.track.prediction import predicted_camera

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
