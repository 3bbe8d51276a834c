"""The global search's stages run ahead on worker processes (broadtrack_graph.track.stage_runner)."""

from __future__ import annotations

import os
from types import SimpleNamespace

import numpy as np
import pytest
from stage_searches import dying_search, numbered_call, numbered_search, stage_numbered_search

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.reinit_policy import ReinitPolicy
from broadtrack_graph.track.stage_runner import StageRunner, default_search_workers
from broadtrack_graph.types.observations import FrameObservations

STAGES = [(k,) for k in range(6)]
PITCH, CURVES, SAMPLING = object(), object(), object()  # the template the workers are given once


def _read(runner, stages=STAGES, count=None, template=(PITCH, CURVES, SAMPLING)):
    results = runner.results(stages, None, None, *template)
    out = []
    for result in results:
        out.append(result)
        if count is not None and len(out) == count:
            break
    results.close()
    return out


@pytest.fixture
def runner_with_a_worker():
    runner = StageRunner(numbered_search, workers=1)
    yield runner
    runner.close()


def test_every_stage_read_in_order_whether_it_ran_here_or_ahead(runner_with_a_worker):
    here = _read(StageRunner(numbered_search, workers=0))
    assert [r.hypothesis for r in here] == [f"stage {k}" for k in range(6)]
    assert {r.reason for r in here} == {f"pid {os.getpid()}"}
    runner = runner_with_a_worker
    for _ in range(2):  # the first search also starts the worker
        ahead = _read(runner)
        assert [r.hypothesis for r in ahead] == [r.hypothesis for r in here]
        assert [r.camera.focal_px for r in ahead] == [r.camera.focal_px for r in here]
    # Stage 1 is handed to the worker as this process starts stage 0, and read from it.
    assert runner.ahead >= 2
    assert len({r.reason for r in ahead}) == 2  # two processes computed them


def test_a_search_stopped_early_drops_the_stages_run_ahead(runner_with_a_worker):
    runner = runner_with_a_worker
    first_two = _read(runner, count=2)
    assert [r.hypothesis for r in first_two] == ["stage 0", "stage 1"]
    # The next search (another frame) reads its own stages, not the dropped ones.
    again = _read(runner, stages=[(10,), (11,), (12,)])
    assert [r.hypothesis for r in again] == ["stage 10", "stage 11", "stage 12"]


def test_labelled_stages_come_with_their_labels_here_and_ahead(runner_with_a_worker):
    stages = [("a", (0,)), ("b", (1,)), ("c", (2,))]
    for runner in (StageRunner(numbered_search, workers=0), runner_with_a_worker):
        read = list(runner.labelled_results(stages, None, None, PITCH, CURVES, SAMPLING))
        assert [(label, r.hypothesis) for label, r in read] == [("a", "stage 0"), ("b", "stage 1"), ("c", "stage 2")]
    assert runner_with_a_worker.ahead >= 1


def test_a_search_with_one_stage_or_another_template_runs_here(runner_with_a_worker):
    runner = runner_with_a_worker
    assert [r.hypothesis for r in _read(runner, stages=[(4,)])] == ["stage 4"]
    assert runner._pool is None  # no worker started for one stage
    _read(runner)
    ahead_before = runner.ahead
    other = _read(runner, template=(object(), CURVES, SAMPLING))
    assert [r.hypothesis for r in other] == [f"stage {k}" for k in range(6)]
    assert runner.ahead == ahead_before and {r.reason for r in other} == {f"pid {os.getpid()}"}


def test_calls_are_mapped_in_order_here_and_on_the_workers_a_search_started(runner_with_a_worker):
    runner = runner_with_a_worker
    calls = [(k,) for k in range(5)]
    here = list(runner.mapped(numbered_call, calls, CURVES, offset=0.5))  # no search has started the worker yet
    assert [r[0] for r in here] == [k + 0.5 for k in range(5)] and {r[1] for r in here} == {os.getpid()}
    assert runner._pool is None
    _read(runner)
    ahead_before = runner.ahead
    ahead = list(runner.mapped(numbered_call, calls, CURVES, offset=0.5))
    assert [r[0] for r in ahead] == [r[0] for r in here] and all(r[2] for r in ahead)  # the worker's template
    assert len({r[1] for r in ahead}) == 2 and runner.ahead > ahead_before
    # Another template than the worker's, or a function that cannot be sent to it: here.
    assert {r[1] for r in runner.mapped(numbered_call, calls, object())} == {os.getpid()}
    assert list(runner.mapped(lambda k, curves: k, calls, CURVES)) == list(range(5))


def test_a_search_that_cannot_be_sent_to_a_worker_runs_here():
    runner = StageRunner(lambda *args: numbered_search(*args), workers=2)
    assert [r.hypothesis for r in _read(runner)] == [f"stage {k}" for k in range(6)]
    assert runner.ahead == 0 and runner._pool is None


def test_a_dead_worker_leaves_the_rest_of_the_run_to_this_process(caplog):
    runner = StageRunner(dying_search, workers=1)
    try:
        for _ in range(2):
            assert [r.hypothesis for r in _read(runner)] == [f"stage {k}" for k in range(6)]
        assert runner._pool is None and "search workers stopped" in caplog.text
    finally:
        runner.close()


def test_no_workers_by_default_outside_the_command_line():
    assert default_search_workers() == 0  # pytest's main module is not broadtrack-graph's



def test_the_policy_decides_the_same_with_workers():
    # Stage 2's camera is confident, stage 4's certain (the search ends there); the others' are not.
    confidence_by_stage = {2: 0.7, 4: 0.95}

    def confidence(camera, *args):
        return confidence_by_stage.get(round(camera.focal_px - 1000.0), 0.3)

    decisions = []
    for workers in (0, 1):
        # every stage (by default a new shot without a known camera searches the default positions alone)
        config = TrackingConfig(search_workers=workers, search_all_places=True)
        policy = ReinitPolicy(config, stage_numbered_search, None, confidence)
        try:
            decision = policy.decide(FrameObservations(0, 1280, 720), SimpleNamespace(marking_mask=np.ones((9, 16), bool)),
                                     PitchTemplate(), CURVES, SAMPLING)  # (the new camera's markings are read)
            decisions.append((decision.camera.focal_px, decision.confidence, decision.camera_id, policy.counts["stages"]))
        finally:
            policy.close()
    assert decisions[0] == decisions[1] == (1004.0, 0.95, "main", 5)
    assert policy.searches.stages.ahead >= 1


def test_workers_of_a_killed_tracker_leave(tmp_path):
    import subprocess
    import sys
    import time
    from pathlib import Path

    script = (
        "import os, sys\n"
        "from stage_searches import numbered_search\n"
        "from broadtrack_graph.track.stage_runner import StageRunner\n"
        "runner = StageRunner(numbered_search, workers=1)\n"
        "list(runner.results([(0,), (1,), (2,)], None, None, 'pitch', 'curves', 'sampling'))\n"
        "print(*runner._pool._processes, flush=True)\n"
        "os._exit(9)  # killed: no shutdown\n"
    )
    tests_dir = str(Path(__file__).resolve().parents[1])
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([tests_dir, os.environ.get("PYTHONPATH", "")])}
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=60, env=env)
    assert done.returncode == 9, done.stderr
    pids = [int(p) for p in done.stdout.split()]
    assert pids
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline and any(_alive(pid) for pid in pids):
        time.sleep(0.2)
    assert not any(_alive(pid) for pid in pids)


def _alive(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as handle:
            return handle.read().split()[2] != "Z"
    except FileNotFoundError:
        return False
