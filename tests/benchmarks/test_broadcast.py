"""``bench broadcast`` end to end on a tiny clip with a stand-in tracker, and the real-video splice.

The stand-in tracker writes the clip's ground truth as its run (cameras on pitch frames, the
true shots, a camera id per line and a tripod per camera): every figure is then known exactly.
"""

from __future__ import annotations

import json
from pathlib import Path
from types import SimpleNamespace

import cv2
import numpy as np
import pytest

from broadtrack_graph.cli import main
from broadtrack_graph.io.broadcast_truth import read_broadcast_truth
from broadtrack_graph.io.cameras import read_camera_file
from broadtrack_graph.io.jsonfile import write_json_atomic
from broadtrack_graph.io.shots_file import SHOTS_FILE, write_shots
from broadtrack_graph.io.track_writer import TrackWriter
from broadtrack_graph.io.tripod_file import tripods_to_json
from broadtrack_graph.types.track_record import TrackRecord

FRAMES, WIDTH, HEIGHT = 24, 320, 180


def truth_as_run(frames_path, out_dir, config=None, detector=None, progress=True, **_):
    """A perfect tracker: the clip's ground truth written as a run folder (with camera ids and shots)."""
    frames_path, out_dir = Path(frames_path), Path(out_dir)
    if frames_path.is_file():  # a video: no camera anywhere
        capture = cv2.VideoCapture(str(frames_path))
        count = int(capture.get(cv2.CAP_PROP_FRAME_COUNT))
        capture.release()
        writer = TrackWriter(out_dir, WIDTH, HEIGHT)
        for i in range(count):
            writer.write(TrackRecord(i, f"{i + 1:06d}", i / 25.0, None, status="failed", reason="stand-in"))
        return SimpleNamespace(summary=writer.close({"timings_s": {"reinit_s": 0.0}}))
    truth = read_broadcast_truth(frames_path)
    writer = TrackWriter(out_dir, WIDTH, HEIGHT)
    for i, cid in enumerate(truth.camera_ids):
        fid = f"{i + 1:06d}"
        if cid is None:
            writer.write(TrackRecord(i, fid, i / 25.0, None, status="other-view", reason="close-up or crowd"))
        else:
            writer.write(TrackRecord(i, fid, i / 25.0, read_camera_file(frames_path / "cameras" / f"camera_{fid}.json")))
    summary = writer.close({"timings_s": {"reinit_s": 0.25}})
    lines = [json.loads(line) for line in (out_dir / "track.jsonl").read_text(encoding="utf-8").splitlines()]
    (out_dir / "track.jsonl").write_text(
        "".join(json.dumps({**line, "camera_id": cid}) + "\n" for line, cid in zip(lines, truth.camera_ids)),
        encoding="utf-8")
    write_shots(out_dir / SHOTS_FILE, truth.shots)
    write_json_atomic(out_dir / "tripod.json", tripods_to_json(truth.tripods))
    return SimpleNamespace(summary=summary)


def write_video(path: Path, frames: int, colour: int) -> None:
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), 25.0, (WIDTH, HEIGHT))
    for i in range(frames):
        writer.write(np.full((HEIGHT, WIDTH, 3), (colour + 2 * i) % 256, np.uint8))
    writer.release()


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    import broadtrack_graph.actions.track as tracking

    base = tmp_path_factory.mktemp("bench-broadcast")
    videos = base / "videos"
    videos.mkdir()
    write_video(videos / "a.mp4", 40, 10)
    write_video(videos / "b.mp4", 30, 120)
    patch = pytest.MonkeyPatch()
    patch.setattr(tracking, "track_input", truth_as_run)
    try:
        out = base / "report.json"
        code = main(["bench", "broadcast", "--frames", str(FRAMES), "--width", str(WIDTH), "--height", str(HEIGHT),
                     "--modes", "online", "batch", "--out", str(base / "work"), "--no-progress", "--json", str(out),
                     "--video-dir", str(videos), "--segment-frames", "10", "--segments", "4",
                     "--real-height", "90"])
    finally:
        patch.undo()
    assert code == 0
    return json.loads(out.read_text(encoding="utf-8"))


def test_report_keys_per_mode(report):
    assert report["suite"] == "broadcast" and set(report["synthetic"]["modes"]) == {"online", "batch"}
    assert report["synthetic"]["truth"]["cameras"] == ["high-behind", "low-16m", "main"]
    for figures in report["synthetic"]["modes"].values():
        assert {"fps", "reinit_time_share", "status_counts", "cuts", "shot_kinds", "camera_ids", "by_kind",
                "cameras_on_no_pitch_frames", "tripods"} <= set(figures)
        assert set(figures["by_kind"]) == {"main", "other-camera"}
        assert {"jac_5", "jac_10", "completeness", "mre_px"} <= set(figures["by_kind"]["main"])


def test_the_truth_scores_perfectly(report):
    figures = report["synthetic"]["modes"]["online"]
    assert figures["cuts"]["recall"] == 1.0 and figures["cuts"]["false_cuts"] == 0
    assert figures["shot_kinds"]["exact_agreement"] == 1.0
    assert figures["camera_ids"]["one_to_one"] is True and figures["camera_ids"]["right_camera_share"] == 1.0
    assert figures["cameras_on_no_pitch_frames"] == 0
    for kind in ("main", "other-camera"):
        assert figures["by_kind"][kind]["completeness"] == 1.0 and figures["by_kind"][kind]["jac_5"] == 1.0
    assert all(t["T_error_m"] == 0.0 for t in figures["tripods"].values())
    assert figures["fps"] == pytest.approx(FRAMES / figures["wall_s"], rel=0.02)
    no_pitch = FRAMES - report["synthetic"]["truth"]["pitch_frames"]
    assert no_pitch > 0 and figures["status_counts"] == {"tracked": FRAMES - no_pitch, "other-view": no_pitch}
    assert figures["reinit_time_share"] == pytest.approx(0.25 / figures["wall_s"], rel=0.02)


def test_real_splice_segments(report):
    real = report["real"]
    # a: 10 frames, b: 12, a again (returning, from frame 10): 8, b again: 12
    assert [(s["source"], s["start"], s["end"], s["source_start"]) for s in real["segments"]] == [
        ("a.mp4", 0, 10, 0), ("b.mp4", 10, 22, 0), ("a.mp4", 22, 30, 10), ("b.mp4", 30, 42, 12)]
    assert real["frames"] == 42 and real["cuts"]["true_cuts"] == 3
    assert all(s["frames_with_camera"] == 0 and s["aligned_share"] is None for s in real["segments"])
    assert real["status_counts"] == {"failed": 42}
    # --real-height alone keeps the 16:9 shape (a stretched frame fits no pinhole camera)
    capture = cv2.VideoCapture(real["video"])
    try:
        assert (capture.get(cv2.CAP_PROP_FRAME_WIDTH), capture.get(cv2.CAP_PROP_FRAME_HEIGHT)) == (160, 90)
    finally:
        capture.release()


def test_splice_width_is_16_by_9():
    from broadtrack_graph.benchmarks.broadcast import splice_width

    assert [splice_width(h) for h in (90, 360, 478, 720, 1080)] == [160, 640, 850, 1280, 1920]
