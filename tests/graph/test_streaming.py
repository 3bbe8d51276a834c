"""The streaming solvers (broadtrack_graph.graph.streaming): one push interface for online and
fixed-lag, and the rebuild after a GTSAM error (injected failures, exact expectations)."""

from __future__ import annotations

import logging

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph import streaming
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.estimates import FrameEstimate
from broadtrack_graph.graph.fixed_lag import FixedLagSmoother
from broadtrack_graph.graph.simulate import SimulationSettings, simulate_frames
from broadtrack_graph.graph.streaming import FixedLagStreamingSolver, OnlineStreamingSolver
from broadtrack_graph.synth.motion import generate_camera_track
from broadtrack_graph.types.observations import FlowMatches, FrameObservations

W, H = 960, 540
START = Camera(1000.0, 0.0, 0.1, 1.3, 0.0, (0.0, 55.0, -12.0), W, H)
FALLBACK = Camera(1100.0, 0.0, 0.2, 1.3, 0.0, (0.0, 55.0, -12.0), W, H)
TRIPOD = Tripod((0.0, 55.0, -12.0), 0.2)


def observations(index: int, flow: bool = True) -> FrameObservations:
    matches = FlowMatches(np.zeros((3, 2)), np.ones((3, 2))) if flow else None
    return FrameObservations(index, W, H, flow=matches)


class StubTracker:
    """Stands in for OnlineTracker: records every add_frame, raises for frames listed in ``fail``."""

    built: list["StubTracker"] = []
    fail: dict[int, int] = {}  # frame index -> failures left

    def __init__(self, width_px, height_px, pitch, graph, tripod) -> None:
        self.tripod = tripod
        self.calls = []
        self.resets = []
        self.held = False  # hold_position_next was called before the next add_frame
        StubTracker.built.append(self)

    def hold_position_next(self):
        self.held = True

    def add_frame(self, obs, guess, trust_previous):
        self.calls.append((obs.frame_index, guess, trust_previous, obs.flow is not None))
        if StubTracker.fail.get(obs.frame_index, 0) > 0:
            StubTracker.fail[obs.frame_index] -= 1
            raise RuntimeError("Indeterminant linear system detected\nwhile working near variable x2")
        return FrameEstimate(obs.frame_index, guess or START)

    def reset(self, camera):
        self.resets.append(camera)


@pytest.fixture
def online(monkeypatch):
    monkeypatch.setattr(streaming, "OnlineTracker", StubTracker)
    StubTracker.built = []
    StubTracker.fail = {}
    solver = OnlineStreamingSolver(W, H, PitchTemplate(), GraphConfig(), TRIPOD)
    assert solver.push(observations(0, flow=False), START, False) == (FrameEstimate(0, START), [FrameEstimate(0, START)])
    assert solver.push(observations(1), None, True)[1] == [FrameEstimate(1, START)]
    return solver


def test_online_releases_each_frame_at_once_and_forwards_reset_and_tripod(online):
    tracker = StubTracker.built[0]
    assert tracker.calls == [(0, START, False, False), (1, None, True, True)]
    online.reset(FALLBACK)
    assert tracker.resets == [FALLBACK]
    assert online.tripod == TRIPOD
    online.tripod = None
    assert tracker.tripod is None
    assert online.finish() == [] and online.rebuilds == 0


def test_one_failure_rebuilds_and_re_adds_the_frame_as_a_fresh_start_without_flow(online, caplog):
    StubTracker.fail = {2: 1}
    with caplog.at_level(logging.WARNING, logger=streaming.__name__):
        current, released = online.push(observations(2), None, True, fallback=FALLBACK)
    assert online.rebuilds == 1 and len(StubTracker.built) == 2
    old, new = StubTracker.built
    assert old.calls[-1] == (2, None, True, True)
    assert new.calls == [(2, FALLBACK, False, False)]  # from the fallback, unlinked, flow dropped
    assert not new.held  # under the wide anchor: the frame's markings may move a wrong start
    assert new.tripod == TRIPOD  # the rebuilt solver keeps the tripod
    assert current == FrameEstimate(2, FALLBACK) and released == [current]
    assert caplog.messages == ["frame 2: solver update failed (Indeterminant linear system detected); "
                               "restarting the solver"]
    # The next frame goes to the rebuilt tracker.
    online.push(observations(3), None, True)
    assert new.calls[-1] == (3, None, True, True)


def test_the_guess_is_preferred_to_the_fallback(online):
    StubTracker.fail = {2: 1}
    current, _ = online.push(observations(2), START, False, fallback=FALLBACK)
    assert StubTracker.built[1].calls == [(2, START, False, False)] and current.camera is START


def test_two_failures_give_a_failed_estimate(online):
    StubTracker.fail = {2: 2}
    current, released = online.push(observations(2), None, True, fallback=FALLBACK)
    assert current == FrameEstimate(2, None, reason="solver failed twice on this frame")
    assert released == [current]
    assert online.rebuilds == 1 and len(StubTracker.built) == 3  # rebuilt again after the second failure
    assert StubTracker.built[2].calls == [] and StubTracker.built[2].tripod == TRIPOD


def test_no_camera_to_restart_from_gives_a_failed_estimate(online):
    StubTracker.fail = {2: 1}
    current, released = online.push(observations(2), None, True)
    assert current == FrameEstimate(2, None, reason="solver failed and no camera to restart from")
    assert released == [current]
    assert online.rebuilds == 1 and StubTracker.built[1].calls == []


@pytest.fixture(scope="module")
def clip():
    pitch = PitchTemplate()
    track = generate_camera_track("main", 8, W, H, seed=7)
    settings = SimulationSettings(line_points=150, flow_matches=200, keypoints=4)
    return pitch, track.cameras, list(simulate_frames(track.cameras, pitch, settings, seed=8))


def test_fixed_lag_releases_late_and_after_a_failure_releases_the_old_window(clip, monkeypatch):
    pitch, truth, frames = clip
    original = FixedLagSmoother.add_frame
    added = []
    fail = {4: 1}

    def flaky(self, obs, initial_guess=None, trust_previous=True):
        added.append((obs.frame_index, initial_guess is not None, trust_previous, obs.flow is not None))
        if fail.get(obs.frame_index, 0) > 0:
            fail[obs.frame_index] -= 1
            raise IndexError("key x4 already marginalised")
        return original(self, obs, initial_guess, trust_previous)

    monkeypatch.setattr(FixedLagSmoother, "add_frame", flaky)
    solver = FixedLagStreamingSolver(W, H, pitch, GraphConfig(), None, lag=2)
    released = []
    for i in range(4):
        current, now = solver.push(frames[i], truth[0] if i == 0 else None, i > 0)
        assert current.frame_index == i and current.camera is not None
        released.append([e.frame_index for e in now])
    assert released == [[], [], [0], [1]]
    solver.tripod = TRIPOD
    first = solver.smoother
    current, now = solver.push(frames[4], None, True, fallback=truth[3])
    assert solver.rebuilds == 1 and solver.smoother is not first and solver.tracker is solver.smoother.tracker
    assert solver.tripod == TRIPOD
    assert [e.frame_index for e in now] == [2, 3]  # the old window, released as it was
    assert all(e.camera is not None for e in now)
    assert current.frame_index == 4 and current.camera is not None
    assert added[-2:] == [(4, False, True, True), (4, True, False, False)]
    after = [[e.frame_index for e in solver.push(frames[i], None, True)[1]] for i in (5, 6, 7)]
    assert after == [[], [4], [5]]
    assert [e.frame_index for e in solver.finish()] == [6, 7]
    assert solver.finish() == []
