"""Tests of benchmarks/endurance_figures.py: the per-block statistics helpers, by hand."""

from __future__ import annotations

import pytest

from broadtrack_graph.benchmarks.endurance_figures import rss_at, slope_per_1000, stats_ms


def test_stats_ms_by_hand_and_empty():
    assert stats_ms([1.0, 2.0, 3.0, 10.0]) == {"median": 2.5, "p90": 7.9, "mean": 4.0, "max": 10.0}
    assert stats_ms([]) == {"median": None, "p90": None, "mean": None, "max": None}


def test_slope_per_1000_frames():
    assert slope_per_1000([0, 1000, 2000], [5.0, 6.0, 7.0]) == pytest.approx(1.0)
    assert slope_per_1000([0, 500, 1000, 1500], [2.0, float("nan"), 1.0, 0.5]) == pytest.approx(-1.0)
    assert slope_per_1000([10], [1.0]) is None
    assert slope_per_1000([10, 10], [1.0, 2.0]) is None


def test_rss_at_takes_the_last_sample_not_after_the_count():
    samples = [(0, 50.0), (100, 60.0), (200, 70.0)]
    assert [rss_at(samples, n) for n in (0, 99, 100, 250)] == [50.0, 50.0, 60.0, 70.0]
    assert rss_at([(10, 1.0)], 5) is None
