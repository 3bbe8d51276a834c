"""``bench real --degrade``: a clip as a lower-league feed shows it, and the video section tracking that copy."""

from __future__ import annotations

import argparse

import cv2
import numpy as np
import pytest

from broadtrack_graph.benchmarks.clip_copy import chained, write_copy
from broadtrack_graph.benchmarks.degrade import Degradation, degrade_change, degrade_frame, parse_degradation
from broadtrack_graph.errors import InputError


def test_the_degradation_is_read_from_width_quality_and_noise():
    assert parse_degradation("854:25:3") == Degradation(854, 25, 3.0)
    assert parse_degradation("640:15:0").label == "640px-q15-n0"
    for bad in ("854:25", "854:25:3:1", "wide:25:3", "854:0:3", "854:101:3", "8:25:3", "854:25:-1"):
        with pytest.raises(argparse.ArgumentTypeError):
            parse_degradation(bad)


def test_a_degraded_frame_is_smaller_noisier_and_the_same_for_the_same_frame():
    rng = np.random.default_rng(0)
    image = np.full((1080, 1920, 3), 90, np.uint8)
    cv2.line(image, (0, 500), (1919, 540), (255, 255, 255), 6)
    image = np.clip(image.astype(int) + rng.integers(-2, 3, image.shape), 0, 255).astype(np.uint8)
    degraded = degrade_frame(image, Degradation(854, 25, 3.0), 7)
    assert degraded.shape == (480, 854, 3) and degraded.dtype == np.uint8
    np.testing.assert_array_equal(degraded, degrade_frame(image, Degradation(854, 25, 3.0), 7))
    assert not np.array_equal(degraded, degrade_frame(image, Degradation(854, 25, 3.0), 8))  # the noise moves
    clean = cv2.resize(image, (854, 480), interpolation=cv2.INTER_AREA).astype(float)
    grass = degraded[100:400, 100:700].astype(float) - clean[100:400, 100:700]
    assert 1.5 < grass.std() < 6.0  # about the noise asked for, blocks and all
    assert degraded[220:240, 427].mean(axis=1).max() > 150  # the line (y = 520 at x = 960) is still there
    # A frame narrower than the width asked keeps its size (made even).
    assert degrade_frame(np.zeros((97, 160, 3), np.uint8), Degradation(854, 50, 0.0)).shape == (96, 160, 3)


def test_the_degraded_copy_of_a_video_has_every_frame_at_its_size(tmp_path, grey_video):
    video = grey_video(320, 180, 4, 120)
    out = tmp_path / "out" / "grey-160.mp4"
    assert write_copy(video, out, chained(degrade_change(Degradation(160, 40, 2.0)))) == 4
    capture = cv2.VideoCapture(str(out))
    ok, first = capture.read()
    capture.release()
    assert ok and first.shape == (90, 160, 3) and abs(first.mean() - 120) < 8  # mp4v twice: a few levels
    with pytest.raises(InputError) as missing:
        write_copy(tmp_path / "none.mp4", tmp_path / "bad.mp4", degrade_change(Degradation(160, 40, 2.0)))
    assert "none.mp4" in str(missing.value)


def test_bench_real_tracks_the_degraded_copy_and_scores_it_on_the_original_frames(bench_real_video_section):
    section, runs = bench_real_video_section("--degrade", "480:40:2")
    name = "main-480px-q40-n2"
    assert section["degraded"] == "480px-q40-n2" and list(section["clips"]) == [name]
    figures = section["clips"][name]
    assert figures["frames"] == 8 and figures["frames_with_camera"] >= 6
    # Scored on the original 640 px frames with the cameras of the 480 px copy, rescaled: aligned.
    assert figures["aligned_share_of_camera_frames"] >= 0.8
    capture = cv2.VideoCapture(str(runs / "copies" / f"{name}.mp4"))
    assert capture.get(cv2.CAP_PROP_FRAME_WIDTH) == 480
    capture.release()
    assert (runs / name / "track.jsonl").is_file()
