"""``bench model``: the figures' arithmetic, and a tiny run of every section."""

from __future__ import annotations

import argparse

import cv2
import pytest

from broadtrack_graph.benchmarks import model as bench_model


def test_summary_arithmetic():
    pitch = [{"camera": True, "ms": 40.0, "keypoints": 3, "keypoint_errors_px": [1.0, 2.0, 9.0],
              "visible_keypoints": 4, "visible_found": 2, "jac5": 0.9},
             {"camera": False, "ms": 50.0, "keypoints": 0, "keypoint_errors_px": [], "visible_keypoints": 2,
              "visible_found": 0, "jac5": 0.0}]
    negatives = [{"camera": False, "ms": 30.0, "keypoints": 1}, {"camera": True, "ms": 35.0, "keypoints": 7}]
    summary = bench_model._summary(pitch + negatives)
    assert summary["pitch_frames"] == 2 and summary["negative_frames"] == 2
    assert summary["keypoints_within_5px"] == pytest.approx(2 / 3, abs=1e-3)
    assert summary["visible_keypoints_found_within_5px"] == pytest.approx(2 / 6, abs=1e-3)
    assert summary["pitch_frames_with_camera"] == 0.5 and summary["pitch_frames_jac5_at_least_80"] == 0.5
    assert summary["negatives_without_camera"] == 0.5
    assert summary["frame_to_camera_ms_median"] == pytest.approx(37.5)


def test_a_tiny_run_reports_every_section(tmp_path):
    from broadtrack_graph.synth.clip import render_clip

    clip = render_clip("main", 3, 640, 360, seed=1)
    writer = cv2.VideoWriter(str(tmp_path / "tiny.mp4"), cv2.VideoWriter_fourcc(*"mp4v"), 25.0, (640, 360))
    for frame in clip.frames:
        writer.write(frame.image)
    writer.release()
    args = argparse.Namespace(model=None, samples=4, presets=["main"], preset_frames=1, width=480, height=272,
                              video_dir=tmp_path, every=2, no_search=False)
    report = bench_model.run(args)
    synthetic = report["synthetic"]
    assert synthetic["all"]["pitch_frames"] + synthetic["all"].get("negative_frames", 0) == 5
    assert "preset main" in synthetic["by_kind"]
    clip_report = report["real"]["clips"]["tiny"]
    assert clip_report["frames_scored"] == 2 and clip_report["resolution"] == "640x360"
    assert 0.0 <= clip_report["model_alone_aligned"] <= 1.0 and 0.0 <= clip_report["search_aligned"] <= 1.0
    assert clip_report["forward_ms_median"] > 0
