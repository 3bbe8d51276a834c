"""TrackWriter: round trips through read_track, interrupted runs, replaced runs."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time

import numpy as np
import pytest

from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.io.cameras import read_camera_file
from broadtrack_graph.io.run_folder import read_track
from broadtrack_graph.io.track_record import record_from_json, record_to_json
from broadtrack_graph.io.track_writer import TrackWriter
from broadtrack_graph.types.status import FrameStatus
from broadtrack_graph.types.track_record import TrackRecord

W, H = 1920, 1080


def camera(t: int) -> Camera:
    return Camera.from_degrees(2000 + 10 * t, -0.03 + 0.001 * t, 5 + 0.5 * t, 75 - 0.1 * t, 0.2, (0.5 * t, 55, -15), W, H)


def records() -> list[TrackRecord]:
    std = {"pan_std_deg": 0.02, "tilt_std_deg": 0.01, "roll_std_deg": 0.005, "focal_std_px": 3.5, "k1_std": 0.002,
           "position_std_m": np.array([0.1, 0.2, 0.3])}
    return [
        TrackRecord(0, "000001", 0.0, camera(0), std, 0.91, False, active_factors=("lines", "tripod")),
        TrackRecord(1, "000002", 0.04, camera(1), {"pan_std_deg": 0.03}, 0.88, False),
        TrackRecord(2, "000003", 0.08, None, confidence=None, status=FrameStatus.NO_PITCH, reason="no marking detected"),
        TrackRecord(3, "000004", 0.12, camera(3), std, 0.62, True, status=FrameStatus.REINITIALISED),
        TrackRecord(4, "000005", 0.16, camera(4), {}, None, False, active_factors=("lines", "flow")),
    ]


def assert_same_camera(a: Camera, b: Camera, tol: float = 1e-9):
    assert (a.width_px, a.height_px) == (b.width_px, b.height_px)
    assert np.allclose(a.to_vector(), b.to_vector(), atol=tol, rtol=0)


def test_round_trip(tmp_path):
    written = records()
    with TrackWriter(tmp_path / "run", W, H, also_960x540=True, run_info={"mode": "online"}) as writer:
        for record in written:
            writer.write(record)
        postfix = writer.progress_postfix()
        assert postfix["conf"] == "-" and postfix["status"] == "tracked" and float(postfix["fps"]) > 0
    track = read_track(tmp_path / "run")
    assert (track.width_px, track.height_px, track.skipped_lines) == (W, H, 0)
    assert [r.frame_id for r in track.records] == [r.frame_id for r in written]
    for got, want in zip(track.records, written):
        assert (got.frame_index, got.status, got.reinitialised, got.reason) == (
            want.frame_index, want.status, want.reinitialised, want.reason)
        assert got.time_s == pytest.approx(want.time_s)
        assert got.confidence == want.confidence
        assert got.active_factors == want.active_factors
        assert set(got.std) == set(want.std)
        for key, value in want.std.items():
            assert np.allclose(got.std[key], value)
        if want.camera is None:
            assert got.camera is None
        else:
            assert_same_camera(got.camera, want.camera)
    # Camera files: only frames with a camera, at both resolutions.
    names = sorted(p.name for p in (tmp_path / "run" / "cameras").iterdir())
    assert names == ["camera_000001.json", "camera_000002.json", "camera_000004.json", "camera_000005.json"]
    full = read_camera_file(tmp_path / "run" / "cameras" / "camera_000004.json")
    assert_same_camera(full, written[3].camera)
    small = read_camera_file(tmp_path / "run" / "cameras_960x540" / "camera_000004.json")
    assert (small.width_px, small.height_px) == (960, 540)
    assert small.focal_px == pytest.approx(written[3].camera.focal_px / 2)
    assert small.k1 == pytest.approx(written[3].camera.k1)
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert summary["complete"] is True
    assert summary["frames_written"] == 5 and summary["frames_with_camera"] == 4
    assert summary["status_counts"]["no-pitch"] == 1 and summary["reinitialisations"] == 1
    assert summary["mean_confidence"] == pytest.approx((0.91 + 0.88 + 0.62) / 3)
    assert summary["run"] == {"mode": "online"}
    assert track.cameras["000003"] is None
    assert np.isnan(track.states()[2]).all() and track.states()[0, 2] == pytest.approx(5.0)


def test_camera_rescaled_to_writer_resolution(tmp_path):
    with TrackWriter(tmp_path, W, H) as writer:
        writer.write(TrackRecord(0, "000001", 0.0, camera(0).rescaled(960, 540)))
    track = read_track(tmp_path)
    assert_same_camera(track.records[0].camera, camera(0), tol=1e-9)
    half = read_track(tmp_path, 960, 540)
    assert half.records[0].camera.focal_px == pytest.approx(1000.0)
    assert (half.width_px, half.height_px) == (960, 540)


def test_truncated_last_line_is_skipped_bad_middle_line_is_an_error(tmp_path):
    writer = TrackWriter(tmp_path, W, H, summary_every=2)
    for record in records()[:4]:
        writer.write(record)
    # An interrupted run: no close(), and half of a fifth line.
    line = json.dumps(record_to_json(records()[4]))
    with open(tmp_path / "track.jsonl", "a") as handle:
        handle.write(line[: len(line) // 2])
    track = read_track(tmp_path)
    assert [r.frame_id for r in track.records] == ["000001", "000002", "000003", "000004"]
    assert track.skipped_lines == 1
    assert track.summary["complete"] is False and track.summary["frames_written"] == 4
    # The same damage in the middle of the file is not an interrupted run.
    lines = (tmp_path / "track.jsonl").read_text().split("\n")
    lines[1] = lines[1][:20]
    (tmp_path / "track.jsonl").write_text("\n".join(lines))
    with pytest.raises(InputError, match="line 2"):
        read_track(tmp_path)


KILL_SCRIPT = """
import os, signal, sys
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.types.track_record import TrackRecord
from broadtrack_graph.io.track_writer import TrackWriter
writer = TrackWriter(sys.argv[1], 1920, 1080, also_960x540=True)
for t in range(40):
    cam = Camera.from_degrees(2000 + t, 0.0, t * 0.1, 75, 0, (0, 55, -15), 1920, 1080)
    writer.write(TrackRecord(t, f"{t + 1:06d}", t / 25, cam, confidence=0.9))
    if t == 24:
        os.kill(os.getpid(), signal.SIGKILL)
"""


def test_killed_run_leaves_every_written_frame_readable(tmp_path):
    out = tmp_path / "run"
    result = subprocess.run([sys.executable, "-c", KILL_SCRIPT, str(out)], capture_output=True, timeout=60)
    assert result.returncode == -signal.SIGKILL
    track = read_track(out)
    assert len(track) == 25 and track.skipped_lines == 0
    assert track.records[-1].camera.focal_px == pytest.approx(2024)
    assert len(list((out / "cameras").glob("camera_*.json"))) == 25
    assert len(list((out / "cameras_960x540").glob("camera_*.json"))) == 25
    assert not [p for p in out.rglob(".*") if p.is_file()]  # no half-written temporary files


def test_new_run_replaces_old_files(tmp_path):
    with TrackWriter(tmp_path, W, H) as writer:
        for record in records():
            writer.write(record)
    with TrackWriter(tmp_path, W, H) as writer:
        writer.write(records()[1])
    assert sorted(p.name for p in (tmp_path / "cameras").iterdir()) == ["camera_000002.json"]
    assert len(read_track(tmp_path)) == 1


def test_exception_inside_writer_keeps_frames_and_marks_summary(tmp_path):
    with pytest.raises(RuntimeError):
        with TrackWriter(tmp_path, W, H) as writer:
            writer.write(records()[0])
            raise RuntimeError("solver exploded")
    track = read_track(tmp_path)
    assert len(track) == 1
    assert track.summary["complete"] is False and "solver exploded" in track.summary["error"]


def test_interrupt_rewrites_the_summary_with_counts_matching_the_files(tmp_path):
    writer = TrackWriter(tmp_path / "run", W, H, summary_every=100)
    for record in records()[:3]:
        writer.write(record)
    stale = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert stale["frames_written"] == 0  # the periodic summary lags behind
    summary = writer.interrupt()
    on_disk = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert on_disk == summary and on_disk["interrupted"] is True and on_disk["complete"] is False
    lines = (tmp_path / "run" / "track.jsonl").read_text().splitlines()
    assert on_disk["frames_written"] == len(lines) == 3
    assert on_disk["frames_with_camera"] == len(list((tmp_path / "run" / "cameras").glob("camera_*.json"))) == 2


def test_keyboard_interrupt_inside_the_writer_marks_interrupted(tmp_path):
    with pytest.raises(KeyboardInterrupt):
        with TrackWriter(tmp_path / "run", W, H) as writer:
            writer.write(records()[0])
            raise KeyboardInterrupt
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    assert summary["interrupted"] is True and summary["frames_written"] == 1


def test_observer_sees_each_record_after_its_line_is_flushed(tmp_path):
    seen = []

    def observer(record, line):
        on_disk = (tmp_path / "run" / "track.jsonl").read_text().splitlines()
        seen.append((record.frame_id, line, json.loads(on_disk[-1]), len(on_disk)))

    with TrackWriter(tmp_path / "run", W, H, on_write=observer) as writer:
        for record in records():
            writer.write(record)
    assert [s[0] for s in seen] == [r.frame_id for r in records()]
    for k, (_, line, last_on_disk, count) in enumerate(seen):
        assert count == k + 1 and json.loads(json.dumps(line)) == last_on_disk
    # the line rebuilds the camera exactly as reading the run back does
    back = read_track(tmp_path / "run").records[3]
    rebuilt = record_from_json(seen[3][1], W, H)
    assert np.array_equal(rebuilt.camera.to_vector(), back.camera.to_vector())


def test_summary_counts_the_processes_cpu_time_since_the_run_began(tmp_path):
    before = time.process_time()
    while time.process_time() - before < 0.05:  # CPU spent before the run: not the run's
        pass
    with TrackWriter(tmp_path / "run", W, H) as writer:
        started = time.process_time()
        while time.process_time() - started < 0.2:  # the run's own work
            sum(range(1000))
        for record in records():
            writer.write(record)
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    spent = time.process_time() - started
    assert 0.2 <= summary["cpu_s"] <= spent + 0.01
    # cpu_s is rounded to the millisecond, so the figure per frame is to a fifth of it
    assert summary["cpu_ms_per_frame"] == pytest.approx(1000 * summary["cpu_s"] / 5, abs=0.11)
    assert summary["cores_used"] == pytest.approx(summary["cpu_s"] / summary["elapsed_s"], rel=0.05)
