"""Default focal points: mirror images through the centre spot and the pan facing it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.reinit.positions import (
    DEFAULT_TRIPOD_POSITIONS_W,
    candidate_positions,
    facing_pan_rad,
    mirrored_position,
)


def test_mirrored_position_is_the_point_reflection_through_the_centre_spot():
    assert mirrored_position((-36.0, 55.0, -12.0)) == (36.0, -55.0, -12.0)  # same height, opposite side
    for position in DEFAULT_TRIPOD_POSITIONS_W.values():
        mirror = mirrored_position(position)
        np.testing.assert_allclose(np.add(position[:2], mirror[:2]), 0.0)  # the centre spot is the midpoint
        assert mirror[2] == position[2]
        assert mirrored_position(mirror) == tuple(position)
    positions = candidate_positions()
    assert positions[:4] == list(DEFAULT_TRIPOD_POSITIONS_W.values())
    assert positions[4:] == [mirrored_position(p) for p in DEFAULT_TRIPOD_POSITIONS_W.values()]
    assert candidate_positions(include_mirrored=False) == positions[:4]


@pytest.mark.parametrize("position", candidate_positions())
def test_facing_pan_looks_at_the_centre_spot(position):
    x, y, z = position
    tilt = math.atan2(math.hypot(x, y), -z)  # tilt 0 looks straight down
    camera = Camera(1000.0, 0.0, facing_pan_rad(position), tilt, 0.0, np.array(position), 960, 540)
    uv, front = camera.project(np.zeros((1, 3)))
    assert front[0]
    np.testing.assert_allclose(uv[0], [480.0, 270.0], atol=1e-6)


def test_facing_pan_of_the_main_camera_and_its_mirror():
    assert facing_pan_rad((0.0, 55.0, -12.0)) == 0.0  # pan 0 looks towards -y
    assert abs(facing_pan_rad((0.0, -55.0, -12.0))) == pytest.approx(math.pi)  # towards +y
    assert facing_pan_rad((-65.0, 0.0, -15.0)) == pytest.approx(math.pi / 2)  # behind the left goal: towards +x
    assert facing_pan_rad((0.0, 0.0, -10.0)) == 0.0  # above the spot: any pan, 0 by convention
