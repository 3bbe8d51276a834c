"""``bench placements --random``: the random cameras stand where broadcast cameras stand and see the pitch."""

from __future__ import annotations

import math

import numpy as np
import pytest

from broadtrack_graph.benchmarks.random_cameras import (
    HFOV_RANGE_DEG,
    MIN_PITCH_SHARE,
    REACH_M,
    STANDS,
    draw_random_camera,
    lens_k1,
    stand_of,
)
from broadtrack_graph.synth.motion import pitch_coverage


def test_200_draws_keep_every_range():
    rng = np.random.default_rng(5)
    drawn = [draw_random_camera(rng, 320, 180) for _ in range(200)]
    positions = np.array([d.camera.position_m for d in drawn])
    x, y, z = positions.T
    assert np.all((np.abs(x) > 52.5) | (np.abs(y) > 34.0)), "a focal point inside the playing area"
    assert np.all(np.hypot(x, y) <= REACH_M)
    assert np.all((-z >= 5.0) & (-z <= 60.0))
    hfov = np.array([math.degrees(2 * math.atan(160.0 / d.camera.focal_px)) for d in drawn])
    assert np.allclose(hfov, [d.hfov_deg for d in drawn])
    assert np.all((hfov >= HFOV_RANGE_DEG[0]) & (hfov <= HFOV_RANGE_DEG[1]))
    assert max(abs(d.camera.roll_deg) for d in drawn) <= 2.0
    k1 = np.array([d.camera.k1 for d in drawn])
    assert np.all((k1 >= -0.01) & (k1 <= 0.1)) and k1.min() < 0 < k1.max()
    assert all(d.pitch_share >= MIN_PITCH_SHARE for d in drawn)
    assert {d.stand for d in drawn} == set(STANDS), "every side, both goals and the corners are drawn"
    # The optical axis goes through the aim point, which lies on the pitch.
    aims = np.array([d.aim_w for d in drawn])
    assert np.all((np.abs(aims[:, 0]) <= 52.5) & (np.abs(aims[:, 1]) <= 34.0))
    uv, _ = drawn[0].camera.project(aims[:1])
    assert np.allclose(uv[0], [160.0, 90.0], atol=1e-6)


def test_the_pitch_share_is_the_kept_views():
    drawn = draw_random_camera(np.random.default_rng(1), 320, 180)
    assert drawn.pitch_share == pytest.approx(pitch_coverage(drawn.camera, margin_m=0.0))
    assert drawn.views_tried >= 1


def test_the_same_stream_draws_the_same_camera():
    a = draw_random_camera(np.random.default_rng([3, 0]), 640, 360)
    b = draw_random_camera(np.random.default_rng([3, 0]), 640, 360)
    assert a.camera.to_vector().tolist() == b.camera.to_vector().tolist()


def test_where_a_camera_stands():
    assert stand_of((0.0, 60.0, -20.0)) == "main stand"
    assert stand_of((52.5, -40.0, -20.0)) == "far side"
    assert stand_of((-60.0, 34.0, -20.0)) == "behind a goal"
    assert stand_of((60.0, -35.0, -20.0)) == "corner"
    assert stand_of((0.0, 0.0, -20.0)) == "pitch"


def test_the_lens_law_is_wide_at_wide_angle_and_near_zero_at_tele():
    assert lens_k1(HFOV_RANGE_DEG[1], 0.09, 0.0) == pytest.approx(0.09)
    assert lens_k1(HFOV_RANGE_DEG[0], 0.09, -0.005) == pytest.approx(-0.005)
    assert 0.0 < lens_k1(25.0, 0.09, 0.0) < 0.09
