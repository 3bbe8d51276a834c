"""Tests of geometry/distortion.py: the SoccerNet distortion model and its inverse."""

import math

import numpy as np
import pytest

from broadtrack_graph.geometry.distortion import (
    ExtraDistortion,
    distort_normalized,
    undistort_normalized,
    unfolded_radius2,
)


def test_full_distortion_model_matches_formula():
    extra = ExtraDistortion((0.01, -0.002, 0.03, 0.001, 0.0005), (0.001, -0.002), (0.0003, 0.0001, -0.0002, 0.0004))
    xy = np.array([[0.1, -0.2], [0.3, 0.25]])
    k1 = -0.1
    out = distort_normalized(xy, k1, extra)
    x, y = xy[1]
    r2 = x * x + y * y
    radial = (1 - 0.1 * r2 + 0.01 * r2**2 - 0.002 * r2**3) / (1 + 0.03 * r2 + 0.001 * r2**2 + 0.0005 * r2**3)
    xd = x * radial + 2 * 0.001 * x * y + -0.002 * (r2 + 2 * x * x) + 0.0003 * r2 + 0.0001 * r2**2
    yd = y * radial + 2 * -0.002 * x * y + 0.001 * (r2 + 2 * y * y) + -0.0002 * r2 + 0.0004 * r2**2
    np.testing.assert_allclose(out[1], [xd, yd], rtol=1e-14)
    np.testing.assert_allclose(undistort_normalized(out, k1, extra), xy, atol=1e-12)


def test_k1_only_distortion_by_hand_and_its_inverse():
    xy = np.array([[0.0, 0.0], [0.3, 0.4], [-0.6, 0.8]])
    out = distort_normalized(xy, 0.2)
    np.testing.assert_allclose(out, [[0.0, 0.0], [0.3 * 1.05, 0.4 * 1.05], [-0.6 * 1.2, 0.8 * 1.2]], rtol=1e-15)
    np.testing.assert_allclose(undistort_normalized(out, 0.2), xy, atol=1e-14)
    assert np.array_equal(undistort_normalized(xy, 0.0), xy)


def test_k1_below_zero_stops_at_the_turning_point():
    k1 = -0.3
    r_turn = 1.0 / math.sqrt(3.0 * -k1)
    r_d_max = r_turn * (1.0 + k1 * r_turn**2)  # = 2 / (3 sqrt(3 |k1|))
    assert r_d_max == pytest.approx(2.0 / (3.0 * math.sqrt(0.9)))
    out = undistort_normalized(np.array([[r_d_max * 1.5, 0.0]]), k1)
    assert out[0, 0] == pytest.approx(r_turn, rel=1e-12) and out[0, 1] == 0.0


def test_unfolded_radius_is_where_the_radial_distortion_stops_growing():
    assert unfolded_radius2(0.0) == math.inf
    assert unfolded_radius2(0.1) == math.inf  # k1 > 0 never folds
    limit = unfolded_radius2(-0.04)
    assert limit == pytest.approx(1.0 / 0.12)
    r = np.sqrt(limit)
    grows = lambda radius: radius * (1.0 - 0.04 * radius**2)  # noqa: E731
    assert grows(r * 0.99) < grows(r) > grows(r * 1.01)
    # With k2 the numeric search finds the same kind of peak.
    extra = ExtraDistortion(radial_k2_k6=(-0.01, 0.0, 0.0, 0.0, 0.0))
    r2 = unfolded_radius2(-0.04, extra)
    radial = lambda q: q * (1.0 - 0.04 * q**2 - 0.01 * q**4)  # noqa: E731
    q = math.sqrt(r2)
    assert r2 < limit and radial(q * 0.99) < radial(q) * 1.0001 and radial(q * 1.01) < radial(q)
