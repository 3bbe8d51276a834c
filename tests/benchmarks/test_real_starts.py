"""Shots started mid-clip (``bench real --starts``): which starts are tried, and how their cameras are scored."""

from __future__ import annotations

import math

import cv2
from drawn_frames import draw_frame

from broadtrack_graph.benchmarks.real_starts import FOUND_WITHIN_FRAMES, score_starts, start_frames, starts_figures
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.io.track_writer import TrackWriter
from broadtrack_graph.types.track_record import TrackRecord

WIDTH, HEIGHT = 640, 360


def test_starts_leave_frames_to_track_and_skip_known_other_views():
    assert start_frames(100, 20, 15) == [0, 20, 40, 60, 80]
    assert start_frames(100, 20, 15, other_views=[(40, 61)]) == [0, 20, 80]
    assert start_frames(10, 20, 15) == [0]  # a clip shorter than a start's frames is tried once


def _run(folder, cameras: dict):
    """A run folder whose track holds ``cameras`` ({frame: camera or None})."""
    track = TrackWriter(folder, WIDTH, HEIGHT)
    for i, camera in sorted(cameras.items()):
        if camera is None:
            track.write(TrackRecord(i, f"{i + 1:06d}", i / 25.0, None, status="unplaced", reason="drawn"))
        else:
            track.write(TrackRecord(i, f"{i + 1:06d}", i / 25.0, camera, confidence=0.8))
    track.close({})
    return folder


def test_each_start_reports_its_first_camera_s_delay_and_the_check_scores_every_camera(tmp_path):
    truth = Camera.from_degrees(700.0, 0.0, 0.0, 74.0, 0.0, (0.0, 55.0, -12.0), WIDTH, HEIGHT)
    tilted = truth.replace(tilt_rad=truth.tilt_rad + math.radians(1.0))
    video = tmp_path / "drawn.mp4"
    writer = cv2.VideoWriter(str(video), cv2.VideoWriter_fourcc(*"mp4v"), 25.0, (WIDTH, HEIGHT))
    for seed in range(6):
        writer.write(draw_frame(truth, seed=seed, players=0)[0])
    writer.release()
    runs = {0: _run(tmp_path / "a", {0: truth, 1: truth, 2: truth}),  # placed at once, aligned
            1: _run(tmp_path / "b", {1: None, 2: None, 3: None}),  # nothing written
            2: _run(tmp_path / "c", {2: None, 3: None, 4: tilted, 5: tilted})}  # placed 2 frames in, a degree off
    rows = score_starts(video, runs)
    assert [(r["start"], r["first_camera_delay"], r["cameras"], r["aligned"], r["misaligned"]) for r in rows] == [
        (0, 0, 3, 3, 0), (1, None, 0, 0, 0), (2, 2, 2, 0, 2)]
    figures = starts_figures(rows, 1, 4)
    assert figures["starts"] == 3 and figures[f"placed_within_{FOUND_WITHIN_FRAMES}"] == 2
    assert figures["not_placed"] == [1] and figures["median_delay_of_placed"] == 1.0
    assert figures["cameras"] == 5 and figures["misaligned"] == 2 and figures["misaligned_share"] == 0.4


def test_bench_real_tracks_every_start_from_nothing(bench_real_video_section):
    section, runs = bench_real_video_section("--starts", "4", "--start-frames", "4")
    figures = section["clips"]["main"]["starts"]
    assert [row["start"] for row in figures["rows"]] == [0, 4]
    assert (runs / "starts" / "main" / "start-00004" / "track.jsonl").is_file()
    assert section["starts"]["starts"] == 2 and "rows" not in section["starts"]
    # The rendered main camera is found on each start's frames, and every camera written is aligned.
    assert figures[f"placed_within_{FOUND_WITHIN_FRAMES}"] == 2 and figures["misaligned"] == 0
