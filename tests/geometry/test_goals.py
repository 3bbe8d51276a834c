"""The goals' image region (broadtrack_graph.geometry.goals)."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.goals import goal_region
from broadtrack_graph.geometry.pitch import PitchTemplate

PITCH = PitchTemplate()


def test_the_region_covers_the_goal_mouth_and_not_the_penalty_spot():
    # A camera behind and beside the right goal, as a high corner camera stands.
    camera = Camera.from_degrees(1500.0, 0.0, -7.0, 72.0, 0.0, (53.0, 70.0, -22.0), 960, 540)
    region = goal_region(camera, 960, 540, PITCH)
    assert region is not None and region.shape == (540, 960)
    points = np.array([[52.5, 0.0, 0.0], [52.5, 0.0, -2.44], [53.5, 3.0, -1.0],  # goal line, crossbar, net
                       [41.5, 0.0, 0.0], [52.5, 20.16, 0.0]])  # penalty spot, a corner of the box
    uv, front = camera.project(points)
    assert front.all() and camera.in_image(uv).all()
    inside = region[np.round(uv[:, 1]).astype(int), np.round(uv[:, 0]).astype(int)]
    assert inside.tolist() == [True, True, True, False, False]
    # Half the size: the same region, scaled.
    half = goal_region(camera, 480, 270, PITCH)
    assert abs(half.mean() - region.mean()) < 0.01


def test_no_region_when_no_goal_is_in_view_or_depth_is_zero():
    centre = Camera.from_degrees(2500.0, 0.0, 0.0, 72.0, 0.0, (0.0, 55.0, -12.0), 960, 540)  # the centre circle
    assert goal_region(centre, 960, 540, PITCH) is None
    side = Camera.from_degrees(1500.0, 0.0, -7.0, 72.0, 0.0, (53.0, 70.0, -22.0), 960, 540)
    assert goal_region(side, 960, 540, PITCH, depth_m=0.0) is None
