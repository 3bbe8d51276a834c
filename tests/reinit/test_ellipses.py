"""Circle hypotheses: turning a direction onto a ray with roll 0, cameras putting a pitch circle on an ellipse."""

from __future__ import annotations

import math

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.reinit.ellipses import _pointing


def test_pointing_turns_a_direction_onto_a_ray_with_roll_zero():
    truth = Camera.from_degrees(2000.0, 0.0, 14.0, 77.0, 0.0, (0.0, 55.0, -12.0), 1920, 1080)
    point_w = np.array([8.0, -5.0, 0.0])
    uv, _ = truth.project(point_w[None])
    ray_c = np.array([uv[0, 0] - 960.0, uv[0, 1] - 540.0, 2000.0])
    solutions = _pointing(point_w - truth.position_m, ray_c)
    assert len(solutions) == 2
    pan, tilt = min(solutions, key=lambda pt: abs(pt[0] - truth.pan_rad))
    assert math.degrees(pan) == pytest.approx(14.0, abs=1e-6) and math.degrees(tilt) == pytest.approx(77.0, abs=1e-6)
