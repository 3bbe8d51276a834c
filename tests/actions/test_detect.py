"""`broadtrack-graph detect` on a small rendered clip: the file it writes, and tracking from it
(broadtrack_graph.actions.detect)."""

import json

import cv2
import numpy as np
import pytest

from broadtrack_graph.actions.detect import export_detections
from broadtrack_graph.actions.track import track_input
from broadtrack_graph.cli import main
from broadtrack_graph.geometry.template import distances_to_polyline, project_template_polylines
from broadtrack_graph.io.annotations import read_annotations
from broadtrack_graph.io.cameras import read_camera_file
from broadtrack_graph.io.detections import read_detections
from broadtrack_graph.io.mask_png import MASK_FIELD_VALUE
from broadtrack_graph.io.run_folder import read_track
from broadtrack_graph.metrics.soccernet import evaluate_cameras
from broadtrack_graph.synth.writer import write_synthetic_clip
from broadtrack_graph.track.config import TrackingConfig

W, H = 1920, 1080  # the weight-free front end is tuned for broadcast resolution
FRAMES = 6


@pytest.fixture(scope="module")
def clip(tmp_path_factory):
    out = tmp_path_factory.mktemp("clip") / "main"
    write_synthetic_clip(out, preset="main", frame_count=FRAMES, width_px=W, height_px=H, seed=3, write_masks=False,
                         progress=False)
    return out


@pytest.fixture(scope="module")
def exported(clip, tmp_path_factory):
    folder = tmp_path_factory.mktemp("detect")
    summary = export_detections(clip, folder / "det.jsonl", track_dir=folder / "naming", progress=False)
    return folder, summary


def _jac5(clip, run_dir) -> dict:
    return evaluate_cameras(read_annotations(clip / "annotations"), read_track(run_dir).cameras, W, H, taus=(5,))


def test_export_writes_one_record_per_frame_with_named_lines_and_masks(clip, exported):
    folder, summary = exported
    assert summary.records == summary.frames == FRAMES and summary.masks == FRAMES
    read = read_detections(folder / "det.jsonl")
    assert read.issues == [] and read.image_size == (W, H)
    assert sorted(read.frames) == list(range(FRAMES))
    assert read.frame_ids[0] == "000001" and read.frame_ids[FRAMES - 1] == f"{FRAMES:06d}"
    mask = cv2.imread(str(read.mask_paths[3]), cv2.IMREAD_GRAYSCALE)
    assert mask is not None and set(np.unique(mask)) <= {0, MASK_FIELD_VALUE, 255}
    assert (mask == 255).sum() > 1000 and (mask == MASK_FIELD_VALUE).mean() > 0.2
    # Named points lie on the marking of their class (true camera), within a few pixels.
    on_line, total = 0, 0
    for index, observations in read.frames.items():
        truth = read_camera_file(clip / "cameras" / f"camera_{index + 1:06d}.json", W, H)
        polylines = project_template_polylines(truth, W, H)
        for name, points in observations.lines_px.items():
            assert name in polylines, f"frame {index}: {name} named but not in view"
            d = distances_to_polyline(points, polylines[name])
            on_line += int((d < 3.0).sum())
            total += len(d)
    assert total > 100 * FRAMES and on_line / total > 0.95


def test_naming_run_is_the_direct_online_track(clip, exported, tmp_path):
    folder, summary = exported
    track_input(clip, tmp_path / "direct", TrackingConfig(mode="online"), progress=False)
    direct = read_track(tmp_path / "direct").states()
    naming = read_track(folder / "naming").states()
    np.testing.assert_allclose(naming, direct, rtol=1e-9, atol=1e-9)


def test_tracking_from_the_file_alone_and_with_frames(clip, exported, tmp_path):
    folder, _ = exported
    track_input(None, tmp_path / "alone", TrackingConfig(mode="online"), detections_path=folder / "det.jsonl",
                progress=False)
    track_input(clip, tmp_path / "frames", TrackingConfig(mode="online"), detections_path=folder / "det.jsonl",
                progress=False)
    for name in ("alone", "frames"):
        report = _jac5(clip, tmp_path / name)
        assert report["completeness"] == 1.0 and report["accuracy"] >= 0.9, name
        assert 0.0 < report["mre_px"] < 1.5
    flows = [("flow" in r.active_factors) for r in read_track(tmp_path / "frames").records]
    assert sum(flows) >= FRAMES // 2
    assert not any("flow" in r.active_factors for r in read_track(tmp_path / "alone").records)
    summary = json.loads((tmp_path / "alone" / "summary.json").read_text())
    assert summary["run"]["detections"].endswith("det.jsonl")


def test_detect_command_writes_the_file(clip, tmp_path, capsys):
    out = tmp_path / "cli" / "d.jsonl"
    assert main(["detect", str(clip), "--out", str(out), "--end", "3", "--no-masks", "--no-progress"]) == 0
    assert "wrote 3 of 3 frames" in capsys.readouterr().out
    read = read_detections(out)
    assert sorted(read.frames) == [0, 1, 2] and read.mask_paths == {}
    assert not (tmp_path / "cli" / "d_masks").exists()
