"""fit_tripod: recovery on observable geometry, robustness to outlier frames, honest
uncertainty on the degenerate main-camera geometry, and refusal of degenerate input."""

from __future__ import annotations

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera, rotation_from_angles
from broadtrack_graph.geometry.tripod import Tripod, focal_point
from broadtrack_graph.graph.tripod_fit import fit_tripod


def cameras_on_tripod(tripod, count, tilt_range_deg, position_noise_m, seed, pan_range_deg=(-40, 40)):
    rng = np.random.default_rng(seed)
    cameras = []
    for _ in range(count):
        pan, tilt = np.radians(rng.uniform(*pan_range_deg)), np.radians(rng.uniform(*tilt_range_deg))
        roll = np.radians(rng.normal(0, 0.2))
        R = rotation_from_angles(pan, tilt, roll)
        C = focal_point(R, tripod, rng.uniform(0.0, 0.5)) + rng.normal(0, position_noise_m, 3)
        cameras.append(Camera(2000.0, 0.0, pan, tilt, roll, C, 960, 540))
    return cameras


@pytest.mark.parametrize("T_w", [(-20.0, 60.0, -18.0), (-75.0, 0.0, -24.0), (36.0, 48.0, -9.0)])
def test_recovers_tripod_anywhere_with_outlier_frames(T_w):
    tripod = Tripod(T_w, 0.3)
    cameras = cameras_on_tripod(tripod, 200, (60, 85), 0.005, seed=1)
    rng = np.random.default_rng(2)
    bad = rng.choice(200, 20, replace=False)
    for i in bad:  # 10 % of frames with a badly wrong focal point
        cameras[i] = cameras[i].replace(position_m=cameras[i].position_m + rng.normal(0, 2.0, 3))
    cameras[5] = None  # a frame without a camera is skipped
    fitted, info = fit_tripod(cameras)
    assert 0.0 < np.linalg.norm(np.subtract(fitted.T_w, T_w)) < 0.05
    assert 0.0 < abs(fitted.delta_m - 0.3) < 0.03
    assert 0.85 < info["inlier_ratio"] < 0.95  # the outlier frames are flagged
    assert 5 not in info["used_frames"]


def test_noise_free_fit_is_exact():
    tripod = Tripod((1.0, 50.0, -15.0), 0.25)
    fitted, info = fit_tripod(cameras_on_tripod(tripod, 30, (70, 85), 0.0, seed=3))
    np.testing.assert_allclose(fitted.as_vector(), tripod.as_vector(), atol=1e-6)
    assert info["rms_inlier_m"] < 1e-6


def test_small_tilt_range_reports_large_delta_uncertainty_and_prior_fixes_it():
    tripod = Tripod((0.0, 55.0, -12.0), 0.22)
    cameras = cameras_on_tripod(tripod, 300, (80, 82), 0.02, seed=4)
    free, free_info = fit_tripod(cameras)
    assert free_info["std_delta_m"] > 0.2  # honestly reported as undetermined
    assert free_info["std_T_m"][0] < 0.05  # while the horizontal position is well determined
    assert abs(free.T_w[0] - tripod.T_w[0]) < 0.1
    prior, prior_info = fit_tripod(cameras, delta_prior_m=0.2, delta_prior_sigma_m=0.1)
    assert prior_info["std_delta_m"] < 0.1
    assert 0.0 < np.linalg.norm(np.subtract(prior.T_w, tripod.T_w)) < 0.3
    assert abs(prior.delta_m - 0.22) < 0.05


def test_degenerate_inputs_return_none_with_reason():
    tripod, info = fit_tripod([None, None])
    assert tripod is None and "cameras" in info["reason"]
    same = Camera(2000.0, 0.0, 0.1, 1.4, 0.0, (0.0, 55.0, -12.0), 960, 540)
    tripod, info = fit_tripod([same] * 10)
    assert tripod is None and "parallel" in info["reason"]


def test_provisional_tripod_inverts_the_model_with_typical_offsets():
    from broadtrack_graph.graph.tripod_fit import provisional_tripod

    tripod = Tripod((36.0, 48.0, -9.0), 0.2)
    rng = np.random.default_rng(4)
    # An opening: 3 deg of pan, lambda exactly the assumed 0.2 m.
    cameras = []
    for _ in range(25):
        pan, tilt = np.radians(rng.uniform(-22, -19)), np.radians(rng.uniform(72.5, 73.5))
        R = rotation_from_angles(pan, tilt, 0.0)
        cameras.append(Camera(2400.0, 0.0, pan, tilt, 0.0, focal_point(R, tripod, 0.2), 1920, 1080))
    found = provisional_tripod(cameras + [None], delta_m=0.2, lambda_m=0.2)
    np.testing.assert_allclose(found.T_w, tripod.T_w, atol=1e-9)
    assert found.sigma_m < 1e-9  # every camera says the same place
    # lambda off by 0.3 m moves T by about 0.3 m along the mean optical axis, no more.
    shifted = provisional_tripod(cameras, delta_m=0.2, lambda_m=0.5)
    assert 0.25 < np.linalg.norm(np.subtract(shifted.T_w, tripod.T_w)) < 0.35
    assert provisional_tripod([None]) is None


def test_a_provisional_tripod_is_as_uncertain_as_its_cameras_disagree_beyond_lambda():
    from broadtrack_graph.graph.tripod_fit import provisional_tripod

    tripod = Tripod((-1.7, 75.0, -18.5), 0.2)
    rng = np.random.default_rng(5)
    cameras, axes = [], []
    for k in range(24):
        pan, tilt = np.radians(rng.uniform(-7, -5)), np.radians(rng.uniform(74, 75))
        R = rotation_from_angles(pan, tilt, 0.0)
        axes.append(R[2])  # the optical axis (r3) in the pitch frame
        cameras.append(Camera(900.0, 0.0, pan, tilt, 0.0, focal_point(R, tripod, 0.2), 848, 478))
    # The focal point moved along the axis with the zoom (lambda 0.05-0.35 m): the scatter the lambda prior allows.
    zoomed = [c.replace(position_m=c.position_m + rng.uniform(-0.15, 0.15) * a) for c, a in zip(cameras, axes)]
    assert provisional_tripod(zoomed, 0.2, 0.2, lambda_sigma_m=0.25).sigma_m == 0.0
    # Half the opening frames 3 m short along the line of sight (a depth a weak view cannot tell), half on it.
    short = [c.replace(position_m=c.position_m - 3.0 * a) if k % 2 else c
             for k, (c, a) in enumerate(zip(cameras, axes))]
    found = provisional_tripod(short, 0.2, 0.2, lambda_sigma_m=0.25)
    implied = np.array([np.asarray(c.position_m) + 0.2 * c.R_cw[1] - 0.2 * c.R_cw[2] for c in short])
    scatter2 = np.mean(np.sum((implied - np.asarray(found.T_w)) ** 2, axis=1))
    assert scatter2 == pytest.approx(1.5**2, rel=1e-3)  # the median lies between the two places: each 1.5 m off
    assert found.sigma_m == pytest.approx(np.sqrt((scatter2 - 0.25**2) / 24), rel=1e-9)
    assert provisional_tripod(short, 0.2, 0.2).sigma_m > found.sigma_m
