"""The two-point method, batched over pairs: focal length from a ray angle, the roll-free projection and its
Jacobian, pan and tilt steps, every pair scored on all keypoints."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.state import rotation_and_derivatives
from broadtrack_graph.reinit.two_point import (
    _pan_tilt_steps,
    _project_roll_free,
    _roll_free_rotations,
    focal_from_ray_angles,
    pair_scores,
    two_point_cameras,
)

W, H = 960, 540


def focal_from_ray_angle(uv_px, angle_rad, width_px, height_px):
    """One pair's focal length, or None."""
    focal = focal_from_ray_angles(np.asarray(uv_px)[None], np.array([angle_rad]), width_px, height_px)[0]
    return None if np.isnan(focal) else focal


def camera_from_two_points(uv_px, points_w, position_w, width_px, height_px):
    """One pair's roll-free camera at position_w, or None."""
    row = two_point_cameras(np.asarray(uv_px)[None], np.asarray(points_w)[None], position_w, width_px, height_px)[0]
    return None if np.isnan(row).any() else Camera(row[0], 0.0, row[1], row[2], 0.0, position_w, width_px, height_px)


def _ray_angle(uv_px, focal, width_px=W, height_px=H):
    a = np.array([uv_px[0][0] - width_px / 2, uv_px[0][1] - height_px / 2, focal])
    b = np.array([uv_px[1][0] - width_px / 2, uv_px[1][1] - height_px / 2, focal])
    return math.acos(a @ b / np.linalg.norm(a) / np.linalg.norm(b))


def test_focal_from_ray_angle_inverts_the_angle():
    uv = np.array([[100.0, 200.0], [800.0, 350.0]])
    for focal in (500.0, 1500.0, 4000.0):
        assert focal_from_ray_angle(uv, _ray_angle(uv, focal), W, H) == pytest.approx(focal, rel=1e-9)
    assert focal_from_ray_angle(uv, math.radians(179), W, H) is None


def test_the_focal_length_is_the_root_where_the_angle_falls_with_f():
    """Two pixels on the same side of the centre: their rays' angle rises with f from the pixels' angle in the image
    (f -> 0), peaks, then falls to 0. A broadcast lens is on the falling side: that root is the one given, even for an
    angle over the f -> 0 one (which a bracket on [0.05, 50] widths would reject)."""
    uv = np.array([[256.96, 347.43], [64.36, 381.81]])
    small_f_angle, focal = _ray_angle(uv, 0.05 * W), 1147.0
    target = _ray_angle(uv, focal)
    assert target > small_f_angle  # over the f -> 0 side's angle
    assert focal_from_ray_angle(uv, target, W, H) == pytest.approx(focal, rel=1e-9)
    # Batched: each pair's own angle; an angle over the peak has no focal length.
    peak = max(_ray_angle(uv, f) for f in np.geomspace(0.05 * W, 50 * W, 2000))
    uv_pairs = np.stack([uv, uv, np.array([[100.0, 200.0], [800.0, 350.0]])])
    got = focal_from_ray_angles(uv_pairs, np.array([target, peak * 1.01, _ray_angle(uv_pairs[2], 2500.0)]), W, H)
    assert got[0] == pytest.approx(focal, rel=1e-9) and np.isnan(got[1]) and got[2] == pytest.approx(2500.0, rel=1e-9)


def test_roll_free_rotations_and_their_derivatives_are_the_state_s_at_roll_0():
    pan, tilt = np.radians([-40.0, 10.0, 170.0]), np.radians([80.0, 95.0, 60.0])
    R, dR_dpan, dR_dtilt = _roll_free_rotations(pan, tilt)
    for k in range(3):
        expected, d_expected = rotation_and_derivatives(pan[k], tilt[k], 0.0)
        np.testing.assert_allclose(R[k], expected, atol=1e-15)
        np.testing.assert_allclose(dR_dpan[k], d_expected[0], atol=1e-15)
        np.testing.assert_allclose(dR_dtilt[k], d_expected[1], atol=1e-15)


def test_the_roll_free_projection_is_the_camera_s_and_its_jacobian_matches_finite_differences():
    position = np.array([2.0, 60.0, -15.0])
    focal, pan, tilt = np.array([900.0, 2100.0]), np.radians([-20.0, 15.0]), np.radians([75.0, 82.0])
    points = np.array([[[-10.0, 5.0, 0.0], [20.0, -8.0, 0.0], [0.0, 0.0, -2.44]],
                       [[30.0, 10.0, 0.0], [25.0, -5.0, 0.0], [40.0, 0.0, 0.0]]])
    uv, front, J = _project_roll_free(focal, pan, tilt, position, points, W, H, want_jacobian=True)
    assert front.all()
    for k in range(2):
        expected, _ = Camera(focal[k], 0.0, pan[k], tilt[k], 0.0, position, W, H).project(points[k])
        np.testing.assert_allclose(uv[k], expected, atol=1e-9)
    h = 1e-7
    for column, (d_pan, d_tilt) in enumerate(((h, 0.0), (0.0, h))):
        plus, _ = _project_roll_free(focal, pan + d_pan, tilt + d_tilt, position, points, W, H)
        minus, _ = _project_roll_free(focal, pan - d_pan, tilt - d_tilt, position, points, W, H)
        np.testing.assert_allclose(J[..., column], (plus - minus) / (2 * h), rtol=1e-5, atol=1e-4)


def test_two_point_method_recovers_a_roll_free_camera():
    truth = Camera.from_degrees(1100.0, 0.0, -12.0, 76.0, 0.0, (0.0, 55.0, -12.0), W, H)
    points_w = np.array([[-20.0, 10.0, 0.0], [15.0, -20.0, 0.0]])
    uv, _ = truth.project(points_w)
    camera = camera_from_two_points(uv, points_w, truth.position_m, W, H)
    assert camera.focal_px == pytest.approx(truth.focal_px, rel=1e-6)
    assert camera.pan_deg == pytest.approx(truth.pan_deg, abs=1e-6)
    assert camera.tilt_deg == pytest.approx(truth.tilt_deg, abs=1e-6)
    assert camera.roll_rad == 0.0
    assert camera_from_two_points(uv[[0, 0]], points_w[[0, 0]], truth.position_m, W, H) is None


def test_every_pair_at_once_gives_the_camera_and_degenerate_pairs_give_nan(broadcast_keypoints):
    truth, uv, pts = broadcast_keypoints
    pairs = np.array(list(itertools.combinations(range(len(uv)), 2)))
    pairs = pairs[np.linalg.norm(uv[pairs[:, 0]] - uv[pairs[:, 1]], axis=1) > 50.0]  # pixels well apart
    cameras = two_point_cameras(uv[pairs], pts[pairs], truth.position_m, truth.width_px, truth.height_px)
    assert len(cameras) >= 20 and np.isfinite(cameras).all()
    np.testing.assert_allclose(cameras[:, 0], truth.focal_px, rtol=1e-6)
    np.testing.assert_allclose(cameras[:, 1:], [[truth.pan_rad, truth.tilt_rad]] * len(cameras), atol=1e-8)
    degenerate = np.stack([
        np.stack([uv[0], uv[0] + 1.0]),  # under 2 px apart
        uv[:2],
    ])
    points = np.stack([pts[:2], np.stack([truth.position_m, pts[1]])])  # the second: a point at the focal point
    assert np.isnan(two_point_cameras(degenerate, points, truth.position_m, truth.width_px, truth.height_px)).all()
    # A pixel that is not a number (a detector's NaN) gives no camera for its pairs, and no error.
    with_nan = uv[pairs[:3]].copy()
    with_nan[0, 1, 0] = np.nan
    cameras = two_point_cameras(with_nan, pts[pairs[:3]], truth.position_m, truth.width_px, truth.height_px)
    assert np.isnan(cameras[0]).all() and np.isfinite(cameras[1:]).all()


def test_pan_tilt_steps_move_the_right_way(broadcast_keypoints):
    """+1 deg of pan moves a point towards -u (about f sin(tilt) / 57 px), +1 deg of tilt towards +v;
    the steps undo an offset of either sign."""
    truth, uv, pts = broadcast_keypoints
    moved_pan, _ = truth.replace(pan_rad=truth.pan_rad + math.radians(1)).project(pts[:1])
    moved_tilt, _ = truth.replace(tilt_rad=truth.tilt_rad + math.radians(1)).project(pts[:1])
    assert moved_pan[0, 0] - uv[0, 0] < -20.0 and abs(moved_pan[0, 1] - uv[0, 1]) < 5.0
    assert moved_tilt[0, 1] - uv[0, 1] > 20.0
    offsets = np.radians([(1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0), (1.5, -1.5)])
    n = len(offsets)
    pan, tilt, ok = _pan_tilt_steps(np.full(n, truth.focal_px), truth.pan_rad + offsets[:, 0],
                                    truth.tilt_rad + offsets[:, 1], truth.position_m, np.broadcast_to(uv[:2], (n, 2, 2)),
                                    np.broadcast_to(pts[:2], (n, 2, 3)), truth.width_px, truth.height_px, steps=4)
    assert ok.all()
    np.testing.assert_allclose(np.degrees(pan), truth.pan_deg, atol=1e-3)
    np.testing.assert_allclose(np.degrees(tilt), truth.tilt_deg, atol=1e-3)


def test_two_point_method_noise_free_and_with_3px_noise(broadcast_keypoints):
    truth, uv, pts = broadcast_keypoints
    W7, H7 = truth.width_px, truth.height_px
    far = np.argmax(np.linalg.norm(uv[:, None] - uv[None], axis=2).max(axis=1))
    other = np.argmax(np.linalg.norm(uv - uv[far], axis=1))
    pair = [far, other]
    camera = camera_from_two_points(uv[pair], pts[pair], truth.position_m, W7, H7)
    assert camera.focal_px == pytest.approx(truth.focal_px, rel=1e-4)
    assert camera.pan_deg == pytest.approx(truth.pan_deg, abs=1e-3)
    assert camera.tilt_deg == pytest.approx(truth.tilt_deg, abs=1e-3)
    rng = np.random.default_rng(0)
    noisy = uv[pair][None] + rng.normal(0, 3.0, (20, 2, 2))
    cameras = two_point_cameras(noisy, np.broadcast_to(pts[pair], (20, 2, 3)), truth.position_m, W7, H7)
    focal_err = np.abs(cameras[:, 0] / truth.focal_px - 1)
    pan_err, tilt_err = np.abs(np.degrees(cameras[:, 1:]) - [truth.pan_deg, truth.tilt_deg]).T
    assert 0 < np.median(focal_err) < 0.01 and max(focal_err) < 0.03
    assert 0 < np.median(pan_err) < 0.1 and 0 < np.median(tilt_err) < 0.1


def test_pair_scores_count_the_keypoints_each_camera_explains(broadcast_keypoints):
    truth, uv, pts = broadcast_keypoints
    off = truth.replace(pan_rad=truth.pan_rad + math.radians(0.3))
    cameras = np.array([[truth.focal_px, truth.pan_rad, truth.tilt_rad], [off.focal_px, off.pan_rad, off.tilt_rad],
                        [np.nan, np.nan, np.nan]])
    count, capped = pair_scores(cameras, truth.position_m, uv, pts, truth.width_px, truth.height_px, 8.0)  # 0.3 deg: ~8 px
    assert count[0] == len(uv) and capped[0] == pytest.approx(0.0, abs=1e-6)
    err = np.linalg.norm(off.project(pts)[0] - uv, axis=1)
    assert 0 < count[1] == (err < 8.0).sum() < len(uv)
    assert capped[1] == pytest.approx(-np.minimum(err, 8.0).sum())
    assert count[2] == -1 and capped[2] == -np.inf
