"""The figures of one real-video run (``bench real --video-dir``), on a drawn clip with known cameras."""

from __future__ import annotations

import json
import math

import cv2
from drawn_frames import draw_frame

from broadtrack_graph.benchmarks.real_video import score_clip
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.io.track_writer import TrackWriter
from broadtrack_graph.types.track_record import TrackRecord

WIDTH, HEIGHT = 640, 360


def test_the_reliability_table_counts_aligned_cameras_by_confidence(tmp_path):
    truth = Camera.from_degrees(700.0, 0.0, 0.0, 74.0, 0.0, (0.0, 55.0, -12.0), WIDTH, HEIGHT)
    video = tmp_path / "drawn.mp4"
    writer = cv2.VideoWriter(str(video), cv2.VideoWriter_fourcc(*"mp4v"), 25.0, (WIDTH, HEIGHT))
    for seed in range(5):
        writer.write(draw_frame(truth, seed=seed, players=0)[0])
    writer.release()
    # Frames 0-1: the true camera, confident; frames 2-3: tilted by a degree at a middling confidence; 4: none.
    tilted = truth.replace(tilt_rad=truth.tilt_rad + math.radians(1.0))
    run = tmp_path / "run"
    track = TrackWriter(run, WIDTH, HEIGHT)
    for i, (camera, confidence) in enumerate([(truth, 0.95), (truth, 0.91), (tilted, 0.55), (tilted, 0.52)]):
        track.write(TrackRecord(i, f"{i + 1:06d}", i / 25.0, camera, confidence=confidence))
    track.write(TrackRecord(4, "000005", 4 / 25.0, None, status="failed", reason="drawn"))
    track.close({})
    figures = score_clip(video, run)
    assert figures["frames"] == 5 and figures["frames_with_camera"] == 4
    assert figures["aligned_share_of_camera_frames"] == 0.5
    reliability = figures["reliability"]
    rows = {row["confidence"]: (row["cameras"], row["right"]) for row in reliability["rows"]}
    assert rows["0.9-1.0"] == (2, 2) and rows["0.5-0.6"] == (2, 0)
    assert reliability["cameras"] == 4 and reliability["written_right_share"] == 0.5
    summary = json.loads((run / "summary.json").read_text())  # the run's cost, as its summary states it
    assert figures["cpu_ms_per_frame"] == summary["cpu_ms_per_frame"] and figures["cores_used"] == summary["cores_used"]
    assert figures["cpu_ms_per_frame"] is not None
