"""Tests of benchmarks/process_stats.py: RSS readings and the per-frame clock around a fake run."""

from __future__ import annotations

import time

from broadtrack_graph.benchmarks import process_stats
from broadtrack_graph.benchmarks.process_stats import FrameClock, peak_rss_mb, rss_mb


class FakeRun:
    def __init__(self) -> None:
        self.seen = []

    def process(self, frame) -> None:
        self.seen.append(frame)
        time.sleep(0.002)


def test_rss_readings_are_plausible():
    now, peak = rss_mb(), peak_rss_mb()
    assert now is not None and 1.0 < now < 1e6
    assert peak is not None and peak >= now * 0.5


def test_frame_clock_times_every_call_and_samples_rss_per_count(monkeypatch):
    readings = iter([100.0, 101.0, 102.0, 103.0, 104.0, 105.0])
    monkeypatch.setattr(process_stats, "rss_mb", lambda: next(readings))
    run = FakeRun()
    clock = FrameClock(run, rss_every=3, block=2)
    assert run.process is clock
    for k in range(6):
        run.process(k)
    assert run.seen == [0, 1, 2, 3, 4, 5]
    assert len(clock.process_ms) == len(clock.cpu_ms) == len(clock.interval_ms) == 6
    assert min(clock.process_ms) >= 1.5  # each call sleeps 2 ms
    assert all(i >= p for i, p in zip(clock.interval_ms, clock.process_ms))
    # start, then at 2 (block), 3 (rss_every), 4 (block), 6 (both, once)
    assert clock.rss == [(0, 100.0), (2, 101.0), (3, 102.0), (4, 103.0), (6, 104.0)]
    clock.sample_rss()  # same count again: not recorded twice
    assert clock.rss[-1] == (6, 104.0) and len(clock.rss) == 5
    assert list(readings) == []  # the repeated sample read 105.0 and dropped it
