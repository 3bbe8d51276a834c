"""``calibrate``: camera files and the preview mosaic from the command line; bad input exits 2."""

from __future__ import annotations

import json

import cv2
import numpy as np
from calibration_frames import H, W, annotation, cameras

from broadtrack_graph.cli import main
from broadtrack_graph.io.annotations import write_annotation_file
from broadtrack_graph.io.cameras import read_camera_file


def test_calibrate_command_writes_camera_files(tmp_path, capsys):
    rng = np.random.default_rng(1)
    folder = tmp_path / "annotations"
    truth = cameras()[0]
    write_annotation_file(folder / "00007.json", annotation(truth, rng))
    out = tmp_path / "cameras"
    preview = tmp_path / "preview.png"
    assert main(["calibrate", "--annotations", str(folder), "--out", str(out), "--width", "960", "--height", "540",
                 "--preview", str(preview), "--no-progress"]) == 0
    image = cv2.imread(str(preview))
    assert image is not None and image.shape == (270, 1440, 3)
    assert (image[:, :480, 1] > 150).sum() > 20  # green points: annotated points within 5 px
    report = json.loads(capsys.readouterr().out)
    assert report["cameras"] == 1 and report["missing_count"] == 0
    camera = read_camera_file(out / "camera_00007.json", W, H)
    uv_true, _ = truth.project(np.array([[0.0, 0.0, 0.0], [-36.0, 20.16, 0.0]]))
    uv_est, _ = camera.project(np.array([[0.0, 0.0, 0.0], [-36.0, 20.16, 0.0]]))
    assert np.max(np.linalg.norm(uv_true - uv_est, axis=1)) < 5.0
    assert main(["calibrate", "--annotations", str(tmp_path / "nowhere"), "--out", str(out)]) == 2
    assert main(["calibrate", "--annotations", str(tmp_path / "annotations"), "--out", str(out), "--width", "1"]) == 2
    assert capsys.readouterr().err.strip().endswith("argument --width: 1 is too small; give an integer >= 2 (see broadtrack-graph calibrate --help)")
