"""Tests of broadtrack_graph.synth.motion: tripod camera tracks."""

from __future__ import annotations

import math

import numpy as np
import pytest

from broadtrack_graph.geometry.tripod import focal_point, tripod_residual, zoom_lambda
from broadtrack_graph.synth.motion import generate_camera_track, k1_from_focal, lambda_from_focal, pitch_coverage
from broadtrack_graph.synth.presets import PRESET_STREAMS, PRESETS


@pytest.mark.parametrize("preset", sorted(PRESETS))
def test_track_is_exactly_on_the_tripod(preset):
    track = generate_camera_track(preset, 120, 640, 360, seed=3)
    assert len(track.cameras) == 120 and track.lambdas_m.shape == (120,) and track.fps == 25.0
    for camera, lam in zip(track.cameras, track.lambdas_m):
        assert abs(tripod_residual(camera.position_m, camera.R_cw, track.tripod)) < 1e-9
        np.testing.assert_allclose(camera.position_m, focal_point(camera.R_cw, track.tripod, lam), atol=1e-12)
        assert zoom_lambda(camera.position_m, camera.R_cw, track.tripod) == pytest.approx(lam, abs=1e-9)
        assert (camera.width_px, camera.height_px) == (640, 360)


def test_deterministic_for_a_seed_and_different_across_seeds():
    a = np.array([c.to_vector() for c in generate_camera_track("main", 60, 480, 270, seed=7).cameras])
    b = np.array([c.to_vector() for c in generate_camera_track("main", 60, 480, 270, seed=7).cameras])
    c = np.array([c.to_vector() for c in generate_camera_track("main", 60, 480, 270, seed=8).cameras])
    np.testing.assert_array_equal(a, b)
    assert np.abs(a - c).max() > 1e-3


def test_every_preset_has_its_own_fixed_random_stream():
    assert sorted(PRESET_STREAMS) == sorted(PRESETS) and len(set(PRESET_STREAMS)) == len(PRESETS)
    # The first six were numbered by sorted name before "low" was added: their clips must not change.
    assert PRESET_STREAMS[:6] == ("16m", "hard", "high-behind", "long", "main", "wide")


def test_low_preset_is_a_closer_lower_camera_with_flatter_views():
    low = generate_camera_track("low", 500, 1280, 720, seed=0)
    main = generate_camera_track("main", 500, 1280, 720, seed=0)
    assert low.tripod.T_w[2] > main.tripod.T_w[2] + 6 and low.tripod.T_w[1] < main.tripod.T_w[1] - 12
    tilt_low = np.degrees([c.tilt_rad for c in low.cameras])
    tilt_main = np.degrees([c.tilt_rad for c in main.cameras])
    assert np.median(tilt_low) > np.median(tilt_main) + 1.5  # closer to horizontal (tilt 90 deg)


def test_main_preset_looks_like_a_broadcast_main_camera():
    track = generate_camera_track("main", 1500, 1920, 1080, seed=1)
    states = np.array([c.to_vector() for c in track.cameras])
    tilt_deg = np.degrees(states[:, 3])
    assert 60.0 < tilt_deg.min() and tilt_deg.max() < 85.0
    # Smooth fluid-head motion: pan speed below 60 deg/s, no frame-to-frame jumps.
    pan_rate = np.degrees(np.abs(np.diff(states[:, 2]))) * track.fps
    assert pan_rate.max() < 60.0
    assert pan_rate.mean() > 0.3  # it does move
    roll_deg = np.degrees(states[:, 4])
    assert np.abs(roll_deg).max() <= PRESETS["main"].roll_max_deg + 1e-9
    coverage = np.array([pitch_coverage(c, grid=12) for c in track.cameras[::10]])
    assert coverage.min() > 0.45 and np.median(coverage) > 0.55
    np.testing.assert_allclose(track.cameras[0].position_m, PRESETS["main"].tripod_T_w, atol=1.0)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_fast_preset_sweeps_at_40_deg_per_s_and_zooms_to_5_deg(seed):
    """What the fast preset is for, read from its cameras (300 frames, the benchmark's seeds): pans of 40 deg/s
    and more on at least 5 % of the frames, shot wide, and (seeds 0 and 1: seed 2's first zoom-in on a player
    comes after frame 300) a zoom from a wide view down to a field of view of 5.5 deg or less."""
    track = generate_camera_track("fast", 300, 1920, 1080, seed=seed)
    pan_rad = np.array([c.pan_rad for c in track.cameras])
    tilt_rad = np.array([c.tilt_rad for c in track.cameras])
    hfov_rad = 2.0 * np.arctan(np.array([c.width_px / 2.0 / c.focal_px for c in track.cameras]))
    pan_rate_deg_s = np.degrees(np.abs(np.diff(pan_rad))) * track.fps
    assert (pan_rate_deg_s >= 40.0).mean() >= 0.05
    assert np.degrees(hfov_rad).max() >= 40.0
    if seed != 2:
        assert np.degrees(hfov_rad).min() <= 5.5
    # Where the widest zoom can hold it, the view turns by at most about a field of view a second: the zoom
    # opens ahead of a sweep (and smoothly: never by more than 10 % of the focal length a frame).
    budget = PRESETS["fast"].max_view_speed_fov_per_s
    axis_rate_rad_s = np.hypot(np.sin(tilt_rad) * np.gradient(pan_rad), np.gradient(tilt_rad)) * track.fps
    holdable = axis_rate_rad_s <= budget * math.radians(PRESETS["fast"].hfov_range_deg[1])
    assert (axis_rate_rad_s / hfov_rad)[holdable].max() < 1.1 * budget
    focal_px = np.array([c.focal_px for c in track.cameras])
    assert np.abs(np.diff(np.log(focal_px))).max() < 0.1


def test_a_short_clip_is_the_beginning_of_a_long_one_with_the_zoom_opened_ahead():
    short = np.array([c.to_vector() for c in generate_camera_track("fast", 120, 960, 540, seed=0).cameras])
    long = np.array([c.to_vector() for c in generate_camera_track("fast", 300, 960, 540, seed=0).cameras])
    np.testing.assert_array_equal(short, long[:120])


def test_zoom_laws_tie_k1_and_lambda_to_focal_length():
    preset = PRESETS["main"]
    wide = (1920 / 2) / math.tan(math.radians(preset.hfov_range_deg[1]) / 2)
    tele = (1920 / 2) / math.tan(math.radians(preset.hfov_range_deg[0]) / 2)
    assert k1_from_focal(preset, wide, 1920) == pytest.approx(preset.k1_wide)
    assert k1_from_focal(preset, tele, 1920) == pytest.approx(preset.k1_tele)
    assert lambda_from_focal(preset, wide, 1920) == pytest.approx(preset.lambda_wide_m)
    assert lambda_from_focal(preset, tele, 1920) == pytest.approx(preset.lambda_tele_m)
    track = generate_camera_track("hard", 400, 960, 540, seed=2)
    focal = np.array([c.focal_px for c in track.cameras])
    k1 = np.array([c.k1 for c in track.cameras])
    order = np.argsort(focal)
    assert np.all(np.diff(k1[order]) <= 1e-12)  # k1 decreases towards tele
    assert k1.min() >= 0.0  # no folding distortion (see the motion module docstring)
    assert np.all(np.diff(track.lambdas_m[order]) >= -1e-12)
    assert focal.max() / focal.min() > 1.5  # the zoom really changes


def test_bad_arguments_raise():
    with pytest.raises(ValueError, match="unknown preset"):
        generate_camera_track("nope", 10, 100, 100)
    with pytest.raises(ValueError, match="frame_count"):
        generate_camera_track("main", 0, 100, 100)
