"""The homography-ground-truth protocol on hand-made cameras and homographies."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.metrics.homography_protocol import (
    clip_figures,
    fit_keypoint_homography,
    frame_figures,
    ground_grid,
    jitter_px,
    project_ground,
)

W, H = 1280, 720


def _camera(pan=-10.0, focal=1500.0):
    return Camera.from_degrees(focal, 0.0, pan, 72.0, 0.0, (0.0, 60.0, -14.0), W, H)


def _homography(camera):
    """The camera's ground homography (k1 0), fitted to exact projections."""
    pts = ground_grid(5.0)
    uv, front = camera.project(np.column_stack([pts, np.zeros(len(pts))]))
    ok = front & (np.abs(uv) < 1e5).all(axis=1)
    Hm, _ = cv2.findHomography(pts[ok], uv[ok], 0)
    return Hm


def test_grid_and_projection():
    grid = ground_grid(1.0)
    assert grid.shape == (105 * 68, 2) and np.allclose(grid.min(axis=0), [-52.0, -33.5])
    uv, valid = project_ground(np.eye(3), np.array([[1.0, 2.0], [3.0, 4.0]]))
    assert valid.all() and np.allclose(uv, [[1.0, 2.0], [3.0, 4.0]])


def test_the_camera_of_the_ground_truth_scores_perfectly():
    camera = _camera()
    gt = _homography(camera)
    figures = frame_figures(camera, gt, W, H)
    assert figures["iou_part"] == pytest.approx(1.0, abs=1e-3)
    assert figures["iou_whole"] == pytest.approx(1.0, abs=1e-3)
    assert 0.0 <= figures["reprojection_px"] < 1e-3
    assert frame_figures(gt, gt, W, H) == {"iou_part": 1.0, "iou_whole": 1.0, "reprojection_px": 0.0}


def test_a_shifted_estimate_loses_iou_and_has_the_shift_as_error():
    gt = np.array([[20.0, 0.0, 640.0], [0.0, 20.0, 360.0], [0.0, 0.0, 1.0]])  # top view, 20 px per metre
    shifted = gt.copy()
    shifted[0, 2] += 30.0  # 30 px = 1.5 m
    figures = frame_figures(shifted, gt, W, H)
    assert figures["reprojection_px"] == pytest.approx(30.0)
    # seen: a 64 x 36 m window; shifted by 1.5 m along x: IoU = 62.5 / 65.5
    assert figures["iou_part"] == pytest.approx(62.5 / 65.5, abs=0.01)
    assert figures["iou_whole"] == 1.0  # the extended views (192 x 108 m) both hold the whole pitch
    assert frame_figures(None, gt, W, H) == {"iou_part": 0.0, "iou_whole": 0.0, "reprojection_px": None}


def test_jitter_is_zero_for_a_constant_offset_and_sees_a_wobble():
    gts = {t: _homography(_camera(pan=-10.0 + 0.2 * t)) for t in range(6)}
    offset = np.array([[1.0, 0.0, 5.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
    steady = {t: offset @ g for t, g in gts.items()}
    assert jitter_px(steady, gts, W, H) == pytest.approx(0.0, abs=1e-6)
    wobble = {t: np.array([[1, 0, 2.0 * (-1) ** t], [0, 1, 0], [0, 0, 1]]) @ g for t, g in gts.items()}
    assert jitter_px(wobble, gts, W, H) == pytest.approx(8.0, rel=1e-6)  # 2 - 2(-2) + 2
    assert jitter_px({0: gts[0]}, gts, W, H) is None


def test_clip_figures_count_missing_frames_as_zero_iou():
    gts = {t: _homography(_camera(pan=-10.0 + 0.2 * t)) for t in range(4)}
    estimates = {0: gts[0], 1: gts[1], 2: None, 3: gts[3]}
    figures = clip_figures(estimates, gts, W, H)
    assert figures["completeness"] == 0.75
    assert figures["iou_part"] == pytest.approx(0.75)
    assert figures["reprojection_px"] == pytest.approx(0.0, abs=1e-6)
    assert figures["jitter_px"] is None


def test_per_frame_baseline_fit():
    gt = _homography(_camera())
    pts = np.array([[-30.0, -20.0], [-10.0, 5.0], [0.0, -9.15], [10.0, 10.0], [25.0, -5.0], [5.0, 20.0]])
    uv, _ = project_ground(gt, pts)
    fitted = fit_keypoint_homography(uv, pts)
    assert frame_figures(fitted, gt, W, H)["reprojection_px"] < 0.05
    assert fit_keypoint_homography(uv[:3], pts[:3]) is None
