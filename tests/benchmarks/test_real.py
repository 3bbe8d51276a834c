"""``bench real``: the TS-WorldCup section on a small synthetic clip folder of the same layout."""

from __future__ import annotations

import json

import cv2
import numpy as np
import pytest

from broadtrack_graph.cli import main
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.metrics.homography_protocol import ground_grid
from broadtrack_graph.synth.motion import generate_camera_track

W, H = 1280, 720
FRAMES = 30


def _write_clip(folder, seed=2):
    """detections.jsonl (ground keypoints with 2 px noise and their world position) + gt_homographies.json."""
    folder.mkdir(parents=True)
    pitch = PitchTemplate()
    cameras = [c.replace(k1=0.0) for c in generate_camera_track("main", FRAMES, W, H, seed=seed).cameras]
    names = sorted(n for n in pitch.keypoints if abs(pitch.keypoints[n][2]) < 1e-9)
    points = pitch.keypoint_array(names)
    grid = ground_grid(4.0)
    rng = np.random.default_rng(seed)
    gt_frames = []
    with (folder / "detections.jsonl").open("w") as handle:
        for t, camera in enumerate(cameras):
            uv, front = camera.project(points)
            keep = front & camera.in_image(uv)
            noisy = uv + rng.normal(0, 2.0, uv.shape)
            entries = [{"id": int(k), "world": points[k].tolist(), "xy": noisy[k].round(2).tolist(), "confidence": 0.7}
                       for k in np.flatnonzero(keep)]
            handle.write(json.dumps({"frame": t, "image_size": [W, H], "units": "px", "keypoints": entries}) + "\n")
            g_uv, g_front = camera.project(np.column_stack([grid, np.zeros(len(grid))]))
            ok = g_front & (np.abs(g_uv) < 1e5).all(axis=1)
            Hm, _ = cv2.findHomography(grid[ok], g_uv[ok], 0)
            gt_frames.append({"frame": t, "H_world_to_image": Hm.tolist()})
    (folder / "gt_homographies.json").write_text(json.dumps({"image_size": [W, H], "frames": gt_frames}))


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    root = tmp_path_factory.mktemp("real")
    _write_clip(root / "data" / "clip-a")
    (root / "data" / "not-a-clip").mkdir()
    path = root / "report.json"
    assert main(["bench", "real", "--tsworldcup", str(root / "data"), "--modes", "online", "fixed-lag",
                 "--out", str(root / "runs"), "--no-progress", "--json", str(path)]) == 0
    return json.loads(path.read_text())


def test_report_has_one_section_per_data_kind_and_every_mode(report):
    section = report["sections"]["tsworldcup"]
    assert list(section["clips"]) == ["clip-a"]
    clip = section["clips"]["clip-a"]
    assert clip["frames"] == FRAMES and set(clip["modes"]) == {"online", "fixed-lag"}
    base = clip["baseline_per_frame_homography"]
    assert base["completeness"] == 1.0 and 0.5 < base["reprojection_px"] < 30.0  # few keypoints: extrapolation
    for mode in ("online", "fixed-lag"):
        figures = clip["modes"][mode]
        assert figures["completeness"] == 1.0
        assert 0.0 < figures["reprojection_px"] < base["reprojection_px"]
        assert 0.0 < figures["jitter_px"] < base["jitter_px"]
        assert figures["iou_part"] > 0.95
        assert set(figures["vs_baseline"]) == {"reprojection", "jitter", "iou_part"}


def test_no_data_folder_is_a_one_line_error(capsys):
    assert main(["bench", "real"]) == 2
    assert "--tsworldcup" in capsys.readouterr().err


def test_opencv_runs_as_in_track_and_is_restored_after(report, monkeypatch, tmp_path):
    # The fps are those a user's `track` gets: the same OpenCV threads (track.feed.default_opencv_threads), and
    # the process's own setting back after the bench.
    from broadtrack_graph.track.feed import default_opencv_threads

    assert report["opencv_threads"] == default_opencv_threads()
    before = cv2.getNumThreads()
    seen = []
    monkeypatch.setattr("broadtrack_graph.benchmarks.real.SECTIONS",
                        {"probe": lambda args: seen.append(cv2.getNumThreads()) or {"ok": True}})
    path = tmp_path / "report.json"
    assert main(["bench", "real", "--threads", "3", "--no-progress", "--json", str(path)]) == 0
    assert seen == [3] and json.loads(path.read_text())["opencv_threads"] == 3
    assert cv2.getNumThreads() == before
