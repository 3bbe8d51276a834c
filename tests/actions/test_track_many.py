"""track-many: units, resume (done units skipped, partial or corrupt ones redone), failures, staged batch, Ray."""

from __future__ import annotations

import json
import os
import sys

import numpy as np
import pytest

from broadtrack_graph.actions.parallel import SerialEngine
from broadtrack_graph.actions.track_many import ManyOptions, plan_units, track_many
from broadtrack_graph.actions.track_units import done_path
from broadtrack_graph.io.manifest import ClipSpec
from broadtrack_graph.io.prefetch import PREFETCH_ENV
from broadtrack_graph.io.run_folder import read_track
from broadtrack_graph.synth.detections_file import write_synthetic_detections
from broadtrack_graph.track.config import TrackingConfig

FRAMES = 30
QUIET = ManyOptions(retries=0, progress=False)


@pytest.fixture(scope="module")
def clips(tmp_path_factory):
    folder = tmp_path_factory.mktemp("detections")
    return [ClipSpec(f"c{seed}", detections=write_synthetic_detections(folder / f"c{seed}.jsonl", FRAMES, seed=seed))
            for seed in range(2)]


def test_each_clip_is_one_unit_and_a_rerun_skips_them(clips, tmp_path):
    report = track_many(clips, tmp_path, options=QUIET)
    assert sorted(report.ran) == ["c0.track", "c1.track"] and not report.failed
    for row in report.clips:
        assert row["frames"] == FRAMES and row["completeness"] == 1.0 and row["mean_confidence"] > 0.5
    stamp = (tmp_path / "c0" / "track.jsonl").stat().st_mtime_ns
    again = track_many(clips, tmp_path, options=QUIET)
    assert again.ran == [] and sorted(again.skipped) == ["c0.track", "c1.track"]
    assert (tmp_path / "c0" / "track.jsonl").stat().st_mtime_ns == stamp
    assert json.loads((tmp_path / "track_many.json").read_text())["skipped"] == again.skipped


def test_corrupt_marker_missing_output_or_changed_options_redo_a_unit(clips, tmp_path):
    track_many(clips, tmp_path, options=QUIET)
    units = {u.id: u for u in plan_units(clips, tmp_path, TrackingConfig())}
    done_path(tmp_path, units["c0.track"]).write_text('{"digest": "trunc')  # a marker cut short
    assert track_many(clips, tmp_path, options=QUIET).ran == ["c0.track"]
    import shutil

    shutil.rmtree(tmp_path / "c1")  # output lost after the marker was written
    assert track_many(clips, tmp_path, options=QUIET).ran == ["c1.track"]
    assert sorted(track_many(clips, tmp_path, TrackingConfig(mode="fixed-lag", lag_frames=3), QUIET).ran) == \
        ["c0.track", "c1.track"]  # other options: other digests
    assert not list(tmp_path.glob(".*tmp-*"))  # no temporary folder left behind


def test_a_failing_unit_is_reported_and_the_others_finish(clips, tmp_path, monkeypatch):
    monkeypatch.setenv("BROADTRACK_FAIL_UNIT", "c1.track")
    report = track_many(clips, tmp_path, options=QUIET, engine=SerialEngine(retries=1))
    assert report.ran == ["c0.track"] and "injected" in report.failed["c1.track"]
    assert "\n" not in report.failed["c1.track"] and not (tmp_path / "c1").exists()
    monkeypatch.delenv("BROADTRACK_FAIL_UNIT")
    assert track_many(clips, tmp_path, options=QUIET).ran == ["c1.track"]


def test_staged_batch_matches_the_same_windows_in_one_process(tmp_path):
    path = write_synthetic_detections(tmp_path / "long.jsonl", 60, seed=4)
    clip = [ClipSpec("long", detections=path)]
    options = ManyOptions(chunk_frames=20, overlap_frames=5, retries=0, progress=False)
    config = TrackingConfig(mode="batch")
    kinds = [u.kind for u in plan_units(clip, tmp_path / "a", config, options)]
    assert kinds == ["pass1"] * 3 + ["tripod"] + ["refine"] * 3 + ["stitch"]
    report = track_many(clip, tmp_path / "a", config, options)
    assert not report.failed and report.clips[0]["frames"] == 60
    records = read_track(tmp_path / "a" / "long").records
    assert [r.frame_index for r in records] == list(range(60))
    assert (tmp_path / "a" / "long" / "tripod.json").is_file()
    # Kill the stitch and one refinement: only those two run again, to the same numbers.
    os.remove(done_path(tmp_path / "a", plan_units(clip, tmp_path / "a", config, options)[-1]))
    os.remove(tmp_path / "a" / "_units" / "long.refine-001.done")
    again = track_many(clip, tmp_path / "a", config, options)
    assert sorted(again.ran) == ["long.refine-001", "long.stitch"] and len(again.skipped) == 6
    redone = read_track(tmp_path / "a" / "long").records
    def cameras(rows):
        return [None if r.camera is None else r.camera.to_vector().tolist() for r in rows]

    assert any(r.camera is not None for r in records) and cameras(records) == cameras(redone)


def test_track_many_on_ray_with_two_local_workers(clips, tmp_path):
    import importlib.util

    if importlib.util.find_spec("ray") is None:
        pytest.skip("Ray not installed (pip install 'broadtrack-graph[scale]')")
    from broadtrack_graph.actions.ray_engine import RayEngine, import_ray

    ray_imported_before = "ray" in sys.modules  # then the loopback setting comes too late
    ray = import_ray(loopback=True)  # before anything else imports ray: a local instance on 127.0.0.1

    serial = track_many(clips, tmp_path / "serial", options=QUIET)
    try:
        with RayEngine(workers=2, retries=0, prefetch=False) as engine:
            report = track_many(clips, tmp_path / "ray", options=QUIET, engine=engine)
            assert engine.nodes() == ["127.0.0.1"] or ray_imported_before
            seen = []
            engine.run(_environment_variable, [("env", (PREFETCH_ENV,))], lambda key, value: seen.append(value),
                       lambda key, error: seen.append(error))
            assert seen == ["0"]  # the units run without the prefetch thread, one CPU each
    finally:
        assert not ray.is_initialized()
    assert sorted(report.ran) == sorted(serial.ran) and not report.failed
    for clip in ("c0", "c1"):
        a = [r.camera.to_vector() for r in read_track(tmp_path / "serial" / clip).records]
        b = [r.camera.to_vector() for r in read_track(tmp_path / "ray" / clip).records]
        assert np.array_equal(a, b)


def _environment_variable(name: str) -> str | None:
    return os.environ.get(name)


def test_prefetch_thread_only_when_a_core_is_left_idle_unless_asked():
    from broadtrack_graph.actions.ray_engine import prefetch_thread

    assert prefetch_thread(None, 1, 2) and not prefetch_thread(None, 2, 2) and not prefetch_thread(None, 4, 2)
    assert not prefetch_thread(False, 1, 2) and prefetch_thread(True, 2, 2)
