"""NBJW / PnLCalib keypoint predictions: the numbering table, the reader, and ``detect --import nbjw``."""

from __future__ import annotations

import json
import zipfile

import numpy as np
import pytest

from broadtrack_graph.cli import main
from broadtrack_graph.errors import InputError
from broadtrack_graph.io.detections import read_detections
from broadtrack_graph.io.nbjw_keypoints import NBJW_KEYPOINTS_W, read_nbjw_predictions
from tests.conftest import SHARED_DATA

TSWC = SHARED_DATA / "ts-worldcup-dev"


def _write_clip(folder, clip="left-match_clip_00001-1", frames=3):
    """Hand-written prediction files: normalised x, y and p per keypoint number (strings), one unknown number."""
    folder.mkdir(parents=True, exist_ok=True)
    for n in range(1, frames + 1):
        data = {"1": {"x": 0.5, "y": 0.25, "p": 0.8}, "5": {"x": 0.75, "y": 0.5, "p": 0.6},
                "12": {"x": 0.1, "y": 0.1, "p": 0.9}, "31": {"x_1": 0.1, "y_1": 0.2, "x_2": 0.3, "y_2": 0.4}}
        if n == 2:
            data["99"] = {"x": 0.5, "y": 0.5, "p": 0.9}
            data["29"] = {"x": 1.7, "y": 0.5, "p": 0.9}  # outside the image: left out
        payload = [data, {}] if n == 3 else data  # both shapes NBJW versions write
        (folder / f"{clip}-IMG_{n:03d}.json").write_text(json.dumps(payload))
    return folder


def test_table_is_in_the_soccernet_frame():
    assert len(NBJW_KEYPOINTS_W) == 73
    assert NBJW_KEYPOINTS_W[1] == (-52.5, -34.0, 0.0)  # far-left corner: y = -34 is the far touchline
    assert NBJW_KEYPOINTS_W[30] == (52.5, 34.0, 0.0)
    assert NBJW_KEYPOINTS_W[51] == (0.0, 0.0, 0.0)
    assert NBJW_KEYPOINTS_W[50][0] == -NBJW_KEYPOINTS_W[52][0] == -9.15
    assert all(NBJW_KEYPOINTS_W[k][2] == -2.44 for k in (12, 15, 16, 19))  # crossbar ends, z down
    ground = [p for k, p in NBJW_KEYPOINTS_W.items() if k not in (12, 15, 16, 19)]
    assert all(abs(x) <= 52.5 and abs(y) <= 34.0 and z == 0.0 for x, y, z in ground)


def test_table_matches_the_id_world_pairs_of_the_shared_detections():
    files = sorted(TSWC.glob("*/detections.jsonl"))
    if not files:
        pytest.skip(f"TS-WorldCup detections not found under {TSWC} (only present beside the CI clone)")
    checked = 0
    for path in files:
        for line in path.read_text().splitlines():
            for keypoint in json.loads(line).get("keypoints", []):
                assert np.allclose(NBJW_KEYPOINTS_W[keypoint["id"]], keypoint["world"], atol=0.011), keypoint
                checked += 1
    assert checked > 1000


def test_reader_converts_to_pixels_and_reports_unknown_numbers(tmp_path):
    folder = _write_clip(tmp_path / "pred")
    result = read_nbjw_predictions(folder, 1280, 720)
    assert [o.frame_index for o in result.frames] == [0, 1, 2]
    assert result.frame_ids[0] == "left-match_clip_00001-1-IMG_001"
    kp = result.frames[0].keypoints
    assert result.keypoint_ids[0] == [1, 5, 12]
    assert np.allclose(kp.uv_px[0], [640.0, 180.0]) and np.allclose(kp.points_w[1], [-36.0, -20.16, 0.0])
    assert np.allclose(kp.confidence, [0.8, 0.6, 0.9])
    assert result.keypoint_ids[2] == [1, 5, 12]  # the [keypoints, lines] shape
    assert len(result.issues) == 1 and "unknown keypoint number '99'" in result.issues[0]


def test_reader_reads_zip_and_picks_a_clip(tmp_path):
    _write_clip(tmp_path / "a", "left-one_clip-1")
    _write_clip(tmp_path / "a", "right-two_clip-2", frames=2)
    archive = tmp_path / "test_pred.zip"
    with zipfile.ZipFile(archive, "w") as handle:
        for path in (tmp_path / "a").iterdir():
            handle.write(path, path.name)
    with pytest.raises(InputError, match="2 clips"):
        read_nbjw_predictions(archive, 960, 540)
    result = read_nbjw_predictions(archive, 960, 540, clip="right-two_clip-2")
    assert len(result.frames) == 2
    with pytest.raises(InputError, match="no numbered prediction"):
        read_nbjw_predictions(archive, 960, 540, clip="nope")


def test_detect_import_nbjw_writes_a_detections_file(tmp_path, capsys):
    folder = _write_clip(tmp_path / "pred")
    out = tmp_path / "det.jsonl"
    assert main(["detect", "--import", "nbjw", str(folder), "--width", "1280", "--height", "720",
                 "--out", str(out)]) == 0
    assert "imported 3 frames" in capsys.readouterr().out
    detections = read_detections(out)
    assert sorted(detections.frames) == [0, 1, 2]
    assert np.allclose(detections.frames[0].keypoints.points_w[2], [-52.5, -3.66, -2.44])
    first = json.loads(out.read_text().splitlines()[0])
    assert [k["id"] for k in first["keypoints"]] == [1, 5, 12]
    assert main(["detect", "--import", "nbjw", str(folder), "--out", str(out)]) == 2  # no image size
