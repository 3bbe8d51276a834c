"""Re-initialisation from keypoints: focal length from a ray angle, the two-point method, RANSAC over pairs."""

from __future__ import annotations

import math

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.io.nbjw_keypoints import NBJW_KEYPOINTS_W
from broadtrack_graph.reinit.keypoints import (
    camera_from_keypoints,
    camera_from_two_points,
    focal_from_ray_angle,
    reinit_from_keypoints,
)
from broadtrack_graph.synth.field_cameras import aim_angles

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


# ------------------------------------------------------------------ two-point method on a broadcast camera (1280x720)

W7, H7 = 1280, 720
TRIPOD = (-0.7, 65.9, -13.9)


def _broadcast(pan=-43.0, tilt=84.0, focal=1480.0):
    return Camera.from_degrees(focal, 0.0, pan, tilt, 0.0, TRIPOD, W7, H7)


def _ground_keypoints(camera):
    names = [n for n in PITCH.keypoints if abs(PITCH.keypoints[n][2]) < 1e-9]
    pts = PITCH.keypoint_array(names)
    uv, front = camera.project(pts)
    ok = front & camera.in_image(uv)
    return uv[ok], pts[ok]


def test_pan_tilt_steps_move_the_right_way():
    """+1 deg of pan moves a point towards -u (about f sin(tilt) / 57 px), +1 deg of tilt towards +v;
    the steps undo an offset of either sign."""
    from broadtrack_graph.reinit.keypoints import _pan_tilt_steps

    truth = _broadcast()
    uv, pts = _ground_keypoints(truth)
    moved_pan, _ = truth.replace(pan_rad=truth.pan_rad + math.radians(1)).project(pts[:1])
    moved_tilt, _ = truth.replace(tilt_rad=truth.tilt_rad + math.radians(1)).project(pts[:1])
    assert moved_pan[0, 0] - uv[0, 0] < -20.0 and abs(moved_pan[0, 1] - uv[0, 1]) < 5.0
    assert moved_tilt[0, 1] - uv[0, 1] > 20.0
    for d_pan, d_tilt in ((1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0), (1.5, -1.5)):
        start = truth.replace(pan_rad=truth.pan_rad + math.radians(d_pan), tilt_rad=truth.tilt_rad + math.radians(d_tilt))
        fixed = _pan_tilt_steps(start, uv[:2], pts[:2], steps=4)
        assert fixed.pan_deg == pytest.approx(truth.pan_deg, abs=1e-3)
        assert fixed.tilt_deg == pytest.approx(truth.tilt_deg, abs=1e-3)


def test_two_point_method_noise_free_and_with_3px_noise():
    truth = _broadcast()
    uv, pts = _ground_keypoints(truth)
    far = np.argmax(np.linalg.norm(uv[:, None] - uv[None], axis=2).max(axis=1))
    other = np.argmax(np.linalg.norm(uv - uv[far], axis=1))
    pair = [far, other]
    camera = camera_from_two_points(uv[pair], pts[pair], TRIPOD, W7, H7)
    assert camera.focal_px == pytest.approx(truth.focal_px, rel=1e-4)
    assert camera.pan_deg == pytest.approx(truth.pan_deg, abs=1e-3)
    assert camera.tilt_deg == pytest.approx(truth.tilt_deg, abs=1e-3)
    rng = np.random.default_rng(0)
    focal_err, pan_err, tilt_err = [], [], []
    for _ in range(20):
        noisy = uv[pair] + rng.normal(0, 3.0, (2, 2))
        camera = camera_from_two_points(noisy, pts[pair], TRIPOD, W7, H7)
        focal_err.append(abs(camera.focal_px / truth.focal_px - 1))
        pan_err.append(abs(camera.pan_deg - truth.pan_deg))
        tilt_err.append(abs(camera.tilt_deg - truth.tilt_deg))
    assert 0 < np.median(focal_err) < 0.01 and max(focal_err) < 0.03
    assert 0 < np.median(pan_err) < 0.1 and 0 < np.median(tilt_err) < 0.1


def test_ransac_with_30_percent_wrong_ids_and_3px_noise_at_candidate_positions():
    """Keypoints with 3 px noise, 30 % of them labelled with another keypoint's position; the focal point is
    unknown (the default candidates are tried, none at the true place): the camera still lands within a few px."""
    truth = _broadcast()
    uv, pts = _ground_keypoints(truth)
    assert len(uv) >= 10
    rng = np.random.default_rng(1)
    noisy = uv + rng.normal(0, 3.0, uv.shape)
    labels = pts.copy()
    wrong = rng.choice(len(uv), int(round(0.3 * len(uv))), replace=False)
    names = [n for n in PITCH.keypoints if abs(PITCH.keypoints[n][2]) < 1e-9]
    others = PITCH.keypoint_array(names)
    for k in wrong:
        choices = [p for p in others if np.linalg.norm(p - pts[k]) > 5.0]
        labels[k] = choices[rng.integers(len(choices))]
    result = reinit_from_keypoints(noisy, labels, W7, H7)
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
