"""Re-initialisation from keypoints: RANSAC over pairs of the two-point method, the keypoint homography."""

from __future__ import annotations

import math

import numpy as np
import pytest

from broadtrack_graph.geometry.aim import aim_angles
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.io.nbjw_keypoints import NBJW_KEYPOINTS_W
from broadtrack_graph.reinit.keypoints import camera_from_keypoints, reinit_from_keypoints

W, H = 960, 540
PITCH = PitchTemplate()


def _camera(pan=-12.0, tilt=76.0, focal=1100.0, k1=0.0, position=(1.5, 57.0, -13.0), roll=0.3):
    return Camera.from_degrees(focal, k1, pan, tilt, roll, position, W, H)


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


# ------------------------------------------------------------------ a broadcast camera (1280x720)

def test_ransac_with_30_percent_wrong_ids_and_3px_noise_at_candidate_positions(broadcast_keypoints):
    """Keypoints with 3 px noise, 30 % of them labelled with another keypoint's position; the focal point is
    unknown (the default candidates are tried, none at the true place): the camera still lands within a few px."""
    truth, uv, pts = broadcast_keypoints
    rng = np.random.default_rng(1)
    noisy = uv + rng.normal(0, 3.0, uv.shape)
    labels = pts.copy()
    wrong = rng.choice(len(uv), int(round(0.3 * len(uv))), replace=False)
    names = [n for n in PITCH.keypoints if abs(PITCH.keypoints[n][2]) < 1e-9]
    others = PITCH.keypoint_array(names)
    for k in wrong:
        choices = [p for p in others if np.linalg.norm(p - pts[k]) > 5.0]
        labels[k] = choices[rng.integers(len(choices))]
    result = reinit_from_keypoints(noisy, labels, truth.width_px, truth.height_px)
    assert result.camera is not None
    good = np.setdiff1d(np.arange(len(uv)), wrong)
    est, _ = result.camera.project(pts[good])
    error = np.linalg.norm(est - uv[good], axis=1)
    assert 0.0 < np.median(error) < 4.0
    assert result.score.inlier_share == pytest.approx(len(good) / len(uv), abs=0.11)


NBJW_W = np.array([NBJW_KEYPOINTS_W[k] for k in range(1, 58)], float)


def _aimed(focal, position, aim, roll_deg=0.0):
    """A camera at position whose optical axis passes through the ground point aim."""
    position, aim = np.asarray(position, float), np.array([*aim, 0.0])
    pan, tilt = aim_angles(position, aim)
    return Camera(focal, 0.0, pan, tilt, math.radians(roll_deg), position, W, H)


@pytest.mark.parametrize("truth", [
    _aimed(1100.0, (1.5, 57.0, -13.0), (-10.0, 0.0), 0.3),  # main camera
    _aimed(1350.0, (67.0, 3.7, -14.3), (40.0, 0.0), -0.4),  # high behind the goal
    _aimed(1600.0, (35.0, 47.0, -8.0), (45.0, 5.0), 0.2),  # low on the 16 m line
    _aimed(830.0, (3.0, 60.0, -27.0), (0.0, 0.0)),  # tactical
])
def test_camera_from_keypoints_finds_a_camera_wherever_it_stands(truth):
    rng = np.random.default_rng(3)
    uv, front = truth.project(NBJW_W)
    seen = front & truth.in_image(uv)
    assert seen.sum() >= 6
    noisy = uv[seen] + rng.normal(0.0, 1.5, (seen.sum(), 2))
    noisy[0] += 80.0  # one keypoint badly off: RANSAC leaves it out
    result = camera_from_keypoints(noisy, NBJW_W[seen], W, H)
    assert result.hypothesis == "keypoint homography"
    assert result.score.tp == seen.sum() - 1
    estimate, _ = result.camera.project(NBJW_W[seen])
    assert np.median(np.linalg.norm(estimate - uv[seen], axis=1)) < 2.5
    assert np.linalg.norm(result.camera.position_m - truth.position_m) < 3.0


def test_camera_from_keypoints_falls_back_to_the_two_point_method_with_three_keypoints():
    truth = _camera(roll=0.0, position=(0.0, 55.0, -12.0))
    uv, front = truth.project(NBJW_W)
    seen = np.flatnonzero(front & truth.in_image(uv))[:3]
    result = camera_from_keypoints(uv[seen], NBJW_W[seen], W, H)
    assert result.camera is not None and result.hypothesis.startswith("two-point")
    assert camera_from_keypoints(uv[seen[:1]], NBJW_W[seen[:1]], W, H).camera is None


def test_a_keypoint_that_is_not_a_number_is_an_outlier(broadcast_keypoints):
    truth, uv, pts = broadcast_keypoints
    uv = uv.copy()
    uv[3] = np.nan  # a detector's NaN
    result = reinit_from_keypoints(uv, pts, truth.width_px, truth.height_px, positions_w=[truth.position_m])
    assert result.camera is not None
    estimate, _ = result.camera.project(pts)
    assert np.nanmedian(np.linalg.norm(estimate - uv, axis=1)) < 1.0
