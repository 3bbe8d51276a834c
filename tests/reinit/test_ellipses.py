"""Circle hypotheses: turning a direction onto a ray with roll 0, the gap of many cameras' circles to an ellipse."""

from __future__ import annotations

import math

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.ellipses import _circle_gaps, _pointing


def test_pointing_turns_a_direction_onto_a_ray_with_roll_zero():
    truth = Camera.from_degrees(2000.0, 0.0, 14.0, 77.0, 0.0, (0.0, 55.0, -12.0), 1920, 1080)
    point_w = np.array([8.0, -5.0, 0.0])
    uv, _ = truth.project(point_w[None])
    ray_c = np.array([uv[0, 0] - 960.0, uv[0, 1] - 540.0, 2000.0])
    solutions = _pointing(point_w - truth.position_m, ray_c)
    assert len(solutions) == 2
    pan, tilt = min(solutions, key=lambda pt: abs(pt[0] - truth.pan_rad))
    assert math.degrees(pan) == pytest.approx(14.0, abs=1e-6) and math.degrees(tilt) == pytest.approx(77.0, abs=1e-6)


def test_circle_gaps_match_the_cameras_own_projection():
    """The gaps of many roll-0 cameras at once equal those measured one camera at a time with Camera.project:
    the median distance from each ellipse point to the nearest projected circle sample."""
    position = np.array([0.0, 55.0, -12.0])
    circle_w = PitchTemplate().sample_uniform(1.0, classes=["Circle central"])["Circle central"]
    truth = Camera.from_degrees(2600.0, 0.0, 3.0, 70.0, 0.0, position, 1920, 1080)
    on, front = truth.project(circle_w)
    on = on[front][::2] + np.random.default_rng(0).normal(0.0, 1.5, (int(front.sum() + 1) // 2, 2))
    pans = np.radians([3.0, 5.0, -4.0, 3.0, 180.0])  # the last looks away from the circle
    tilts = np.radians([70.0, 71.0, 69.0, 70.0, 70.0])
    focals = np.array([2600.0, 2400.0, 2900.0, 3100.0, 2600.0])
    gaps = _circle_gaps(pans, tilts, focals, circle_w - position, on, 1920, 1080)
    for k in range(4):
        camera = Camera(focals[k], 0.0, pans[k], tilts[k], 0.0, position, 1920, 1080)
        uv, seen = camera.project(circle_w)
        one_at_a_time = np.median(np.min(np.linalg.norm(on[:, None, :] - uv[seen][None, :, :], axis=2), axis=1))
        assert gaps[k] == pytest.approx(one_at_a_time, rel=1e-9)
    assert gaps[0] < 3.0 and gaps[1] > 20.0  # the true camera fits; one 2 deg off does not
    assert np.isnan(gaps[4])  # fewer than 3 circle samples in front of it
