"""RunFolder and read_track: the layout, cameras, summary, tripod, records read back, camera folders."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.io.cameras import read_camera_file, write_camera_file
from broadtrack_graph.io.run_folder import RunFolder, read_track
from broadtrack_graph.io.track_writer import TrackWriter
from broadtrack_graph.types.status import FrameStatus
from broadtrack_graph.types.track_record import TrackRecord

W, H = 1920, 1080


def camera(t: int) -> Camera:
    return Camera.from_degrees(2000 + 10 * t, -0.03 + 0.001 * t, 5 + 0.5 * t, 75 - 0.1 * t, 0.2, (0.5 * t, 55, -15), W, H)


def assert_same_camera(a: Camera, b: Camera, tol: float = 1e-9):
    assert (a.width_px, a.height_px) == (b.width_px, b.height_px)
    assert np.allclose(a.to_vector(), b.to_vector(), atol=tol, rtol=0)


def test_layout(tmp_path):
    run = RunFolder(tmp_path / "run")
    assert run.track_path == tmp_path / "run" / "track.jsonl"
    assert run.summary_path == tmp_path / "run" / "summary.json"
    assert run.tripod_path == tmp_path / "run" / "tripod.json"
    assert run.camera_path("000042") == tmp_path / "run" / "cameras" / "camera_000042.json"
    assert run.camera_path(7, at_960x540=True) == tmp_path / "run" / "cameras_960x540" / "camera_00007.json"
    assert run.pass1().path == tmp_path / "run" / "pass1"
    assert run.pass1().track_path == tmp_path / "run" / "pass1" / "track.jsonl"
    assert not (run.has_track() or run.has_summary() or run.has_tripod())
    assert run.camera_files() == {} and run.count_track_lines() == 0 and run.recorded_detections() is None


def test_cameras_written_and_listed(tmp_path):
    run = RunFolder(tmp_path)
    run.create(also_960x540=True)
    relative = run.write_camera("000003", camera(3), also_960x540=True)
    assert relative == "cameras/camera_000003.json"
    assert_same_camera(read_camera_file(tmp_path / relative), camera(3))
    assert_same_camera(read_camera_file(run.camera_path("000003", at_960x540=True)), camera(3).rescaled(960, 540))
    assert run.camera_files() == {"000003": run.camera_path("000003")}
    assert run.remove_camera_files() == 2 and run.camera_files() == {}


def test_create_fails_with_one_line_error(tmp_path):
    (tmp_path / "file").write_text("x")
    with pytest.raises(InputError, match="cannot create output folder"):
        RunFolder(tmp_path / "file" / "run").create()


def test_records_round_trip_and_summary_reread(tmp_path):
    written = [TrackRecord(0, "000001", 0.0, camera(0), {"pan_std_deg": 0.5}, 0.9),
               TrackRecord(1, "000002", 0.04, None, status=FrameStatus.NO_PITCH, reason="no marking"),
               TrackRecord(2, "000003", 0.08, camera(2), {}, 0.7, True)]
    info = {"input": "clip.mp4", "detections": "det/detections.jsonl"}
    with TrackWriter(tmp_path, W, H, run_info=info) as writer:
        for record in written:
            writer.write(record)
    run = RunFolder(tmp_path)
    assert run.count_track_lines() == 3
    summary = run.read_summary()
    assert summary["complete"] is True and summary["frames_written"] == 3 and summary["frames_with_camera"] == 2
    assert summary["run"] == info and summary["mean_confidence"] == pytest.approx(0.8)
    assert run.recorded_detections() == Path("det/detections.jsonl")
    track = run.read_track()
    assert [r.frame_id for r in track.records] == ["000001", "000002", "000003"]
    assert track.records[1].camera is None and track.records[1].reason == "no marking"
    assert_same_camera(track.records[2].camera, camera(2))
    assert track.records[0].std == {"pan_std_deg": 0.5} and track.summary == summary
    # A rewritten summary is what the next reader sees.
    run.write_summary({**summary, "note": "checked"})
    assert json.loads(run.summary_path.read_text())["note"] == "checked"
    assert read_track(run.track_path).summary["note"] == "checked"  # the track.jsonl path works too
    half = run.read_track(960)
    assert (half.width_px, half.height_px) == (960, 540)
    assert_same_camera(half.records[0].camera, camera(0).rescaled(960, 540))


def test_tripod_round_trip(tmp_path):
    run = RunFolder(tmp_path)
    run.write_tripod(Tripod((1.5, 56.0, -12.25), 0.2), {"frames": 150, "inlier_ratio": 0.9, "residuals_m": np.zeros(3),
                                                        "main-1": {"provisional": True, "inliers": np.ones(3, bool)}})
    assert run.has_tripod()
    tripod = run.read_tripod()
    assert tuple(tripod.T_w) == (1.5, 56.0, -12.25) and tripod.delta_m == 0.2
    assert json.loads(run.tripod_path.read_text())["fit"] == {"frames": 150, "inlier_ratio": 0.9,
                                                               "main-1": {"provisional": True}}


def test_summary_errors_name_the_file(tmp_path):
    run = RunFolder(tmp_path)
    with pytest.raises(InputError, match="summary.json: file not found"):
        run.read_summary()
    run.summary_path.write_text("{")
    with pytest.raises(InputError, match="summary.json: malformed JSON"):
        run.read_summary()


def test_read_camera_folder(tmp_path):
    for t in (4, 2, 10):
        write_camera_file(tmp_path / f"camera_{t:05d}.json", camera(t), 960, 540)
    track = read_track(tmp_path)
    assert [r.frame_id for r in track.records] == ["00002", "00004", "00010"]
    assert [r.frame_index for r in track.records] == [2, 4, 10]
    assert (track.width_px, track.height_px) == (960, 540)
    assert_same_camera(track.records[2].camera, camera(10).rescaled(960, 540), tol=1e-9)
    rescaled = read_track(tmp_path, W, H)
    assert_same_camera(rescaled.records[0].camera, camera(2), tol=1e-9)


def test_read_track_errors(tmp_path):
    with pytest.raises(InputError, match="run folder not found"):
        read_track(tmp_path / "nope")
    with pytest.raises(InputError, match="neither track.jsonl nor camera"):
        read_track(tmp_path)


def test_clear_removes_what_a_run_owns_and_nothing_else(tmp_path):
    from broadtrack_graph.io.run_folder import RUN_ENTRIES

    folder = RunFolder(tmp_path / "run")
    folder.create(also_960x540=True)
    for name in ("tripod.json", "shots.json", "summary.json", "track.jsonl", "notes.txt"):
        (folder.path / name).write_text("{}", encoding="utf-8")
    (folder.path / "pass1" / "cameras").mkdir(parents=True)
    (folder.path / "cameras" / "camera_00001.json").write_text("{}", encoding="utf-8")
    (folder.path / "mine").mkdir()
    removed = folder.clear()
    assert sorted(removed) == sorted(RUN_ENTRIES)
    assert sorted(p.name for p in folder.path.iterdir()) == ["mine", "notes.txt"]
    assert folder.clear() == []  # nothing left to remove; no error
