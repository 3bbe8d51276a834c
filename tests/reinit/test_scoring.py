"""Per-class agreement of a camera with labelled line points."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateSampling
from broadtrack_graph.reinit.scoring import score_labelled

W, H = 960, 540
PITCH = PitchTemplate()
SAMPLING = TemplateSampling(PITCH)


def test_score_labelled_is_perfect_for_the_true_camera_and_drops_when_it_turns():
    truth = Camera.from_degrees(1100.0, 0.0, -12.0, 76.0, 0.0, (1.5, 57.0, -13.0), W, H)
    lines = {}
    for name, pts in PITCH.sample_uniform(0.5).items():
        uv, front = truth.project(pts)
        ok = front & np.all((uv > 10.0) & (uv < [W - 10.0, H - 10.0]), axis=1)  # clear of the border
        if ok.sum() >= 4:
            lines[name] = uv[ok][np.linspace(0, ok.sum() - 1, 12).astype(int)]
    assert len(lines) >= 4
    score = score_labelled(truth, lines, 5.0, SAMPLING)
    assert score.fn == 0 and score.tp == len(lines)
    assert score.inlier_share == 1.0 and score.mean_distance_px < 0.5
    assert score.jaccard == 1.0 and score.fp == 0  # every projected class is detected
    turned = score_labelled(truth.replace(pan_rad=truth.pan_rad + np.radians(2.0)), lines, 5.0, SAMPLING)
    assert turned.tp < score.tp and turned.inlier_share < 0.5 and turned.mean_distance_px > 10.0
    missing = score_labelled(truth, {**lines, "Not a class": np.array([[10.0, 10.0]])}, 5.0, SAMPLING)
    assert missing.fn == 1  # detected but never projected
