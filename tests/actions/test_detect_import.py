"""Detections files without images: the annotation importer, the `detect` command line, forgiving tracking,
and the keypoint experiment's helpers (broadtrack_graph.actions.detect, benchmarks.detections)."""

import json

import numpy as np
import pytest

from broadtrack_graph.actions.detect import import_annotations
from broadtrack_graph.actions.track import track_input
from broadtrack_graph.benchmarks.detections import noisy_keypoint_records
from broadtrack_graph.benchmarks.template_error import template_errors_px
from broadtrack_graph.cli import main
from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import project_template_polylines
from broadtrack_graph.io.annotations import write_annotation_file, write_gamestate_labels
from broadtrack_graph.io.detections import read_detections
from broadtrack_graph.io.run_folder import read_track
from broadtrack_graph.synth.motion import generate_camera_track
from broadtrack_graph.track.config import TrackingConfig

W, H = 960, 540


def _lines(x: float) -> dict:
    return {"Middle line": np.array([[x, 0.1], [x, 0.9]]), "Side line top": np.array([[0.1, 0.2], [0.9, 0.25]])}


def test_import_folder_keeps_frame_numbers_and_reports_what_it_leaves_out(tmp_path):
    folder = tmp_path / "annotations"
    write_annotation_file(folder / "000001.json", _lines(0.5))
    write_annotation_file(folder / "000004.json", {**_lines(0.25), "Line unknown": np.array([[0.3, 0.3]])})
    (folder / "000005.json").write_text("{broken")
    summary = import_annotations(folder, tmp_path / "ann.jsonl", W, H)
    assert summary.records == 2
    assert any("000005" in s for s in summary.skipped) and any("Line unknown" in s for s in summary.skipped)
    read = read_detections(tmp_path / "ann.jsonl")
    assert read.issues == []
    assert sorted(read.frames) == [0, 3]  # 000004 is frame 3: the gap stays a gap
    assert read.frame_ids == {0: "000001", 3: "000004"}
    # SoccerNet's pixel rule x * (W - 1), y * (H - 1).
    np.testing.assert_allclose(read.frames[3].lines_px["Middle line"], [[0.25 * (W - 1), 0.1 * (H - 1)],
                                                                        [0.25 * (W - 1), 0.9 * (H - 1)]])
    assert set(read.frames[3].lines_px) == {"Middle line", "Side line top"}


def test_import_folder_numbered_from_zero_and_explicit_first_number(tmp_path):
    folder = tmp_path / "annotations"
    write_annotation_file(folder / "00000.json", _lines(0.5))
    write_annotation_file(folder / "00002.json", _lines(0.4))
    import_annotations(folder, tmp_path / "a.jsonl", W, H)
    assert sorted(read_detections(tmp_path / "a.jsonl").frames) == [0, 2]
    summary = import_annotations(folder, tmp_path / "b.jsonl", W, H, first_number=2)
    assert sorted(read_detections(tmp_path / "b.jsonl").frames) == [0] and summary.skipped


def test_import_gamestate_uses_its_image_order_and_size(tmp_path):
    frames = {"000001": _lines(0.5), "000002": None, "000003": _lines(0.3)}
    write_gamestate_labels(tmp_path / "Labels-GameState.json", frames, 1280, 720)
    import_annotations(tmp_path, tmp_path / "gs.jsonl")
    read = read_detections(tmp_path / "gs.jsonl")
    assert sorted(read.frames) == [0, 2] and read.image_size == (1280, 720)
    np.testing.assert_allclose(read.frames[2].lines_px["Middle line"][0], [0.3 * 1279, 0.1 * 719])


def test_import_errors_are_one_line(tmp_path):
    folder = tmp_path / "annotations"
    write_annotation_file(folder / "000001.json", _lines(0.5))
    with pytest.raises(InputError, match="image size"):
        import_annotations(folder, tmp_path / "x.jsonl")
    with pytest.raises(InputError, match="not found"):
        import_annotations(tmp_path / "nowhere", tmp_path / "x.jsonl", W, H)


def test_detect_command_line(tmp_path, capsys):
    folder = tmp_path / "annotations"
    write_annotation_file(folder / "000001.json", _lines(0.5))
    assert main(["detect", "--annotations", str(folder), "--width", "960", "--height", "540",
                 "--out", str(tmp_path / "d.jsonl")]) == 0
    assert "imported 1 annotated frames" in capsys.readouterr().out
    assert main(["detect", str(tmp_path), "--annotations", str(folder), "--out", str(tmp_path / "e.jsonl")]) == 2
    assert main(["detect", "--out", str(tmp_path / "e.jsonl")]) == 2
    assert main(["detect", str(tmp_path), "--mode", "batch", "--out", str(tmp_path / "e.jsonl")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 3 and "--mode must be online" in err


def _projected_records(cameras, every: int = 6) -> list[dict]:
    """Detections-file records of the template projected with the true cameras (every n-th point per class)."""
    records = []
    for index, camera in enumerate(cameras):
        polylines = project_template_polylines(camera, W, H)
        lines = {name: np.round(points[::every], 2).tolist() for name, points in polylines.items() if len(points) >= 2}
        records.append({"frame": index, "frame_id": f"{index + 1:06d}", "image_size": [W, H], "lines": lines})
    return records


def test_bad_items_and_a_truncated_file_never_stop_tracking(tmp_path):
    cameras = generate_camera_track("main", 16, W, H, seed=2).cameras
    records = _projected_records(cameras)
    records[3]["lines"]["Penalty spot"] = [[10, 10]]  # unknown class
    records[4]["keypoints"] = [{"name": "Nowhere", "xy": [5, 5]}, {"name": "Centre spot", "xy": [float("nan"), 1]},
                               {"name": "Centre spot", "xy": [5000, 1]}, {"name": "Centre spot", "xy": [5, 5],
                                                                          "confidence": 0.01}]
    records[5]["lines"]["Middle line"] = [[float("nan"), 3.0]] + records[5]["lines"].get("Middle line", [])
    del records[8]  # a frame without detections
    text = "".join(json.dumps(r) + "\n" for r in records[:-1]) + json.dumps(records[-1])[:40]  # truncated last line
    path = tmp_path / "lines.jsonl"
    path.write_text(text)
    result = track_input(None, tmp_path / "run", TrackingConfig(mode="online"), detections_path=path, progress=False)
    track = read_track(tmp_path / "run")
    assert [r.frame_index for r in track.records] == list(range(15))  # the truncated frame 15 is not there
    assert track.records[8].status == "motion-prior" and "no detections" in track.records[8].reason
    assert track.records[8].camera is None and track.records[9].camera is not None  # carried, no camera claimed
    assert result.summary["run"]["detection_issues"] >= 6
    pitch = PitchTemplate()
    points_w = np.vstack(list(pitch.sample_uniform(1.0).values()))
    errors = [np.mean(template_errors_px(r.camera, cameras[r.frame_index], points_w)) for r in track.records
              if r.camera is not None]
    assert 0.0 < np.median(errors) < 2.0 and max(errors) < 8.0


def test_noisy_keypoint_records_have_the_asked_noise_and_mislabels():
    pitch = PitchTemplate()
    cameras = generate_camera_track("main", 60, 1920, 1080, seed=1).cameras
    keypoints, ids = [], []
    for index, camera in enumerate(cameras):
        names = sorted(pitch.keypoints)
        uv, front = camera.project(pitch.keypoint_array(names))
        keep = front & camera.in_image(uv)
        keypoints.append({n: uv[k] for k, n in enumerate(names) if keep[k]})
        ids.append(f"{index + 1:06d}")
    records, counts = noisy_keypoint_records(keypoints, ids, 1920, 1080, pitch, 5.0, 0.1, seed=0)
    assert counts["keypoints"] == sum(len(k) for k in keypoints) > 200
    assert 0.05 < counts["mislabelled"] / counts["keypoints"] < 0.15
    residuals, wrong = [], 0
    for record, truth in zip(records, keypoints):
        names = [e["name"] for e in record["keypoints"]]
        assert len(names) == len(set(names)) and all(n in pitch.keypoints for n in names)
        for entry in record["keypoints"]:
            if entry["name"] in truth:
                residuals.append(np.subtract(entry["xy"], truth[entry["name"]]))
            else:
                wrong += 1
    assert wrong == counts["mislabelled"]
    std = np.std(np.array(residuals), axis=0)
    assert np.all((std > 4.5) & (std < 5.5))
