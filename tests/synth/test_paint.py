"""Tests of the per-pixel markings: distance fields and the box-filter coverage."""

from __future__ import annotations

import math

import numpy as np
import pytest

from broadtrack_graph.synth.paint import (
    FIELD_MAX_M,
    GroundGrid,
    Strokes,
    coverage,
    distance_field,
    footprint,
    pitch_strokes,
)

GRID = GroundGrid(x_min_m=-10.0, y_min_m=-5.0, texel_m=0.05, rows=200, cols=400)


def _centres():
    xs = GRID.x_min_m + (np.arange(GRID.cols) + 0.5) * GRID.texel_m
    ys = GRID.y_min_m + (np.arange(GRID.rows) + 0.5) * GRID.texel_m
    return np.meshgrid(xs, ys)


def test_the_distance_field_of_a_segment_an_arc_and_a_spot_is_the_analytic_distance():
    strokes = Strokes(np.array([[-8.0, 0.0, -2.0, 0.0]]), np.array([[3.0, 0.0, 2.0, 0.0, math.pi]]),
                      np.array([[-5.0, 3.0, 0.11]]))
    field = distance_field(GRID, strokes)
    X, Y = _centres()
    segment = np.hypot(X - np.clip(X, -8.0, -2.0), Y)
    rho, angle = np.hypot(X - 3.0, Y), np.arctan2(Y, X - 3.0)
    arc = np.where(angle >= 0, np.abs(rho - 2.0), np.minimum(np.hypot(X - 5.0, Y), np.hypot(X - 1.0, Y)))
    spot = np.maximum(np.hypot(X + 5.0, Y - 3.0) - 0.05, 0.0)
    expected = np.minimum(np.minimum(np.minimum(segment, arc), spot), FIELD_MAX_M)
    np.testing.assert_allclose(field, expected, atol=1e-5)


def test_the_pitch_strokes_hold_every_ground_class_the_corner_arcs_and_three_spots():
    strokes = pitch_strokes()
    assert len(strokes.segments) == 17  # the 26 classes less 6 goal tubes and 3 circles
    assert len(strokes.arcs) == 3 + 4 and len(strokes.spots) == 3


def test_coverage_paints_the_width_of_the_line_whatever_the_pixel_size():
    # A line along the image columns: d = |u - u0| * s metres, s metres per pixel.
    for metres_per_px in (0.01, 0.05, 0.3, 1.0):
        u = np.arange(64, dtype=np.float32)
        d = np.abs(u - 31.3) * np.float32(metres_per_px)
        distance = np.minimum(np.tile(d, (4, 1)), FIELD_MAX_M).astype(np.float32)
        unclipped = d < FIELD_MAX_M - 1.01 * metres_per_px  # its neighbours are not clipped either
        np.testing.assert_allclose(footprint(distance)[1][unclipped], metres_per_px, rtol=1e-4)
        alpha = coverage(distance, 0.06)
        assert alpha.min() >= 0 and alpha.max() <= 1
        np.testing.assert_allclose(alpha[1].sum() * metres_per_px, 0.12, rtol=0.02)  # painted width 12 cm
        if metres_per_px <= 0.01:
            assert alpha[1, 31] == 1.0
    with pytest.raises(ValueError):
        coverage(distance, 0.5)
