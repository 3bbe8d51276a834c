"""Truth files of broadcast clips and per-camera tripod files: round trips and malformed input."""

from __future__ import annotations

import json

import pytest

from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.io.broadcast_truth import (
    CAMERA_IDS_TRUTH_FILE,
    TRIPODS_TRUTH_FILE,
    has_broadcast_truth,
    read_broadcast_truth,
    write_broadcast_truth,
)
from broadtrack_graph.io.run_folder import read_frame_camera_ids
from broadtrack_graph.io.tripod_file import read_tripods_by_camera, write_tripod
from broadtrack_graph.types.shot import Shot

SHOTS = [Shot(0, 3, "main", "main", "start", {"main": 3}), Shot(3, 5, "close-up", None, "hard", {"close-up": 2}),
         Shot(5, 7, "other-camera", "high-behind", "hard", {"main": 2})]
TRIPODS = {"main": Tripod((0.0, 55.0, -12.0), 0.22), "high-behind": Tripod((-75.0, 0.0, -24.0), 0.25)}
IDS = ["main"] * 3 + [None] * 2 + ["high-behind"] * 2


def test_truth_round_trip(tmp_path):
    assert not has_broadcast_truth(tmp_path)
    write_broadcast_truth(tmp_path, SHOTS, TRIPODS, IDS)
    assert has_broadcast_truth(tmp_path)
    truth = read_broadcast_truth(tmp_path)
    assert truth.shots == SHOTS and truth.tripods == TRIPODS and truth.camera_ids == IDS


def test_truth_reader_names_the_bad_file(tmp_path):
    write_broadcast_truth(tmp_path, SHOTS, TRIPODS, IDS[:-1])
    with pytest.raises(InputError, match="6 frame ids for shots ending at frame 7"):
        read_broadcast_truth(tmp_path)
    write_broadcast_truth(tmp_path, SHOTS, TRIPODS, IDS)
    (tmp_path / TRIPODS_TRUTH_FILE).write_text('{"main": {"T_w": [0, 1]}}', encoding="utf-8")
    with pytest.raises(InputError, match="tripods_truth.json: cameras.main: expected"):
        read_broadcast_truth(tmp_path)
    write_broadcast_truth(tmp_path, SHOTS, TRIPODS, IDS)
    (tmp_path / CAMERA_IDS_TRUTH_FILE).write_text('{"camera_ids": [1, 2]}', encoding="utf-8")
    with pytest.raises(InputError, match="camera_ids"):
        read_broadcast_truth(tmp_path)


def test_tripods_by_camera_reads_both_forms(tmp_path):
    single = tmp_path / "single.json"
    write_tripod(single, TRIPODS["main"], {"frames": 10})
    assert read_tripods_by_camera(single) == {"main": TRIPODS["main"]}
    assert read_tripods_by_camera(single, default_id="cam0") == {"cam0": TRIPODS["main"]}
    write_broadcast_truth(tmp_path, SHOTS, TRIPODS, IDS)
    assert read_tripods_by_camera(tmp_path / TRIPODS_TRUTH_FILE) == TRIPODS
    nested = tmp_path / "nested.json"
    nested.write_text(json.dumps({"tripods": {"c1": {"T_w": [1, 2, -3], "delta_m": 0.2}}}), encoding="utf-8")
    assert read_tripods_by_camera(nested) == {"c1": Tripod((1.0, 2.0, -3.0), 0.2)}
    nested.write_text("[1]", encoding="utf-8")
    with pytest.raises(InputError):
        read_tripods_by_camera(nested)


def test_frame_camera_ids_with_and_without_the_field(tmp_path):
    lines = [{"frame": 0, "focal_px": 1000.0}, {"frame": 1, "focal_px": None}, {"frame": 2, "focal_px": 900.0,
             "camera_id": "cam-2"}, {"frame": 3, "focal_px": None, "camera_id": None}]
    (tmp_path / "track.jsonl").write_text("\n".join(json.dumps(x) for x in lines) + '\n{"frame": 4, "foc',
                                          encoding="utf-8")
    assert read_frame_camera_ids(tmp_path) == {0: "main", 1: None, 2: "cam-2", 3: None}
    with pytest.raises(InputError):
        read_frame_camera_ids(tmp_path / "nowhere")
