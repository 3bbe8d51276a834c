"""Tests of synth/drawing.py: fixed-point coordinates, projection without the k1 < 0 fold, nearness."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.synth.drawing import any_near_image, fixed_point, project_unfolded


def test_fixed_point_has_four_fractional_bits_and_clips():
    out = fixed_point(np.array([[1.5, -2.25], [1e9, -1e9]]))
    assert out.dtype == np.int32
    assert out.tolist() == [[24, -36], [1_600_000, -1_600_000]]


def test_project_unfolded_drops_points_beyond_the_fold():
    camera = Camera.from_degrees(1000.0, -0.5, 0.0, 90.0, 0.0, [0.0, 0.0, -10.0], 1920, 1080)
    # Looking horizontally along -y: a point at depth 10 m and lateral offset x has r^2 = (x / 10)^2.
    # The fold of k1 = -0.5 is at r^2 = 1 / 1.5, i.e. |x| = 8.165 m.
    points = np.array([[0.0, -10.0, -10.0], [8.0, -10.0, -10.0], [8.3, -10.0, -10.0], [0.0, 10.0, -10.0]])
    uv, valid = project_unfolded(camera, points)
    assert valid.tolist() == [True, True, False, False]
    assert np.allclose(uv[0], [960.0, 540.0])
    _, valid_k0 = project_unfolded(camera.replace(k1=0.0), points)
    assert valid_k0.tolist() == [True, True, True, False]


def test_any_near_image_uses_the_margin_and_ignores_nan():
    assert any_near_image(np.array([[-40.0, 10.0]]), 100, 50)
    assert not any_near_image(np.array([[-60.0, 10.0]]), 100, 50)
    assert not any_near_image(np.array([[-1.0, 10.0]]), 100, 50, margin=0.0)
    assert any_near_image(np.array([[np.nan, 0.0], [5.0, 5.0]]), 100, 50, margin=0.0)
    assert not any_near_image(np.array([[np.nan, np.nan]]), 100, 50)
