"""Tests of synth/objects.py: a player is drawn where the camera sees it, labelled, with its box."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.synth.drawing import SURFACE_PLAYER
from broadtrack_graph.synth.objects import draw_objects
from broadtrack_graph.synth.scene import PlayerTrack


def test_a_player_in_view_gets_pixels_labels_and_a_box():
    camera = Camera.from_degrees(1200.0, 0.0, 0.0, 80.0, 0.0, [0.0, 40.0, -10.0], 640, 360)
    foot = np.array([0.0, 0.0, 0.0])
    uv, _ = camera.project(foot[None])
    players = PlayerTrack(positions_w=foot[None, None], teams=np.array([1]), heights_m=np.array([1.8]),
                          phases=np.zeros((1, 1)))
    image = np.full((360, 640, 3), 90, np.uint8)
    labels = np.zeros((360, 640), np.uint8)
    boxes = draw_objects(camera, image, labels, [], players, 0)
    assert boxes.shape == (1, 5) and boxes[0, 0] == 0
    x0, y0, x1, y1 = boxes[0, 1:]
    assert x0 < uv[0, 0] < x1 and abs(y1 - uv[0, 1]) < 2.0  # the box stands on the foot point
    ys, xs = np.nonzero(labels == SURFACE_PLAYER)
    assert len(xs) > 50
    assert xs.min() >= x0 - 1 and xs.max() <= x1 + 1 and ys.min() >= y0 - 1 and ys.max() <= y1 + 1
    off_player = labels != SURFACE_PLAYER
    assert np.any(image[~off_player] != 90)
    # Nothing in view: no box, nothing drawn.
    away = camera.replace(pan_rad=camera.pan_rad + np.pi)
    image2, labels2 = np.full_like(image, 90), np.zeros_like(labels)
    assert draw_objects(away, image2, labels2, [], players, 0).shape == (0, 5)
    assert not labels2.any()
