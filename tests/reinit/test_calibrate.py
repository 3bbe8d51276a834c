"""One-frame calibration from labelled line points (the worker state of the set-level job)."""

from __future__ import annotations

import numpy as np
from calibration_frames import H, W, annotation, cameras

from broadtrack_graph.io.annotations import annotation_to_pixels
from broadtrack_graph.metrics.soccernet import evaluate_frame
from broadtrack_graph.reinit.calibrate import calibrate_item, calibrate_lines, init_worker
from broadtrack_graph.reinit.lines import ReinitConfig


def test_one_frame_through_the_worker_and_directly():
    truth = cameras()[0]
    lines_norm = annotation(truth, np.random.default_rng(0))
    init_worker(W, H, ReinitConfig())
    result = calibrate_item(("00001", lines_norm))
    assert result.frame_id == "00001" and result.camera is not None and result.reason == ""
    assert evaluate_frame(lines_norm, result.camera, W, H, (5.0,)).jac[5.0] >= 0.85
    direct = calibrate_lines(annotation_to_pixels(lines_norm, W, H), W, H)
    uv_worker, _ = result.camera.project(np.array([[0.0, 0.0, 0.0], [-36.0, 20.16, 0.0]]))
    uv_direct, _ = direct.camera.project(np.array([[0.0, 0.0, 0.0], [-36.0, 20.16, 0.0]]))
    assert np.max(np.linalg.norm(uv_worker - uv_direct, axis=1)) < 1.0
