"""The map score of roll-0 cameras against a marking map drawn here, and the choice of distinct hypotheses."""

from __future__ import annotations

import math
from dataclasses import replace

import cv2
import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.map_score import Hypothesis, MapScorer, best_distinct, polish_locally
from broadtrack_graph.reinit.mask_config import MaskSearchConfig

W, H = 960, 540
PITCH = PitchTemplate()
CONFIG = MaskSearchConfig()


def _drawn_map(camera):
    """The ground template drawn 1 px wide as the camera sees it, and its pixels as marking points."""
    mask = np.zeros((H, W), np.uint8)
    for name, pts in PITCH.sample_uniform(0.1).items():
        if not PITCH.is_on_ground(name):
            continue
        uv, front = camera.project(pts)
        uv = uv[front & np.all(np.abs(uv) < 1e4, axis=1)]
        if len(uv) >= 2:
            cv2.polylines(mask, [np.round(uv).astype(np.int32)], False, 1, 1)
    rows, cols = np.nonzero(mask)
    return mask > 0, np.column_stack([cols, rows]).astype(float)


def test_true_camera_scores_best_and_both_scorings_agree():
    truth = Camera.from_degrees(1300.0, 0.0, 9.0, 77.0, 0.0, (0.0, 55.0, -12.0), W, H)
    mask, points = _drawn_map(truth)
    scorer = MapScorer(mask, points, (W, H), PITCH, CONFIG)
    pans = truth.pan_rad + np.radians([0.0, 1.0, -2.0])
    costs = scorer.costs(truth.position_m, pans, [truth.tilt_rad] * 3, [truth.focal_px] * 3,
                         CONFIG.score_hit_px, CONFIG.score_point_px)
    assert costs[0] < -0.9  # F1 of precision and recall near 1
    assert costs[0] < costs[1] < costs[2]
    for pan, cost in zip(pans, costs):  # the vectorised roll-0 score is the full camera's score
        camera = truth.replace(pan_rad=float(pan))
        assert scorer.camera_cost(camera, CONFIG.score_hit_px, CONFIG.score_point_px) == pytest.approx(cost, abs=0.02)
    looking_up = scorer.costs(truth.position_m, [truth.pan_rad], [math.radians(170.0)], [truth.focal_px],
                              CONFIG.score_hit_px, CONFIG.score_point_px)
    assert looking_up[0] == math.inf  # no template in the image


def test_best_distinct_skips_near_copies_and_infinite_costs():
    f = 1000.0
    pans = np.array([0.0, 0.001, 0.1, 0.0, 0.2])
    tilts = np.zeros(5)
    focals = np.array([f, f, f, 2 * f, f])
    costs = np.array([-0.9, -0.95, -0.5, -0.7, np.inf])
    # index 1 is best; 0 is 1 px from it (a near copy); 3 has the same angles but twice the focal length.
    assert best_distinct(pans, tilts, focals, costs, 10, 5.0, 960) == [1, 3, 2]
    assert best_distinct(pans, tilts, focals, costs, 2, 5.0, 960) == [1, 3]


def test_polish_locally_brings_a_shifted_hypothesis_onto_the_map_and_leaves_the_rest():
    truth = Camera.from_degrees(1300.0, 0.0, 9.0, 77.0, 0.0, (0.0, 55.0, -12.0), W, H)
    mask, points = _drawn_map(truth)
    scorer = MapScorer(mask, points, (W, H), PITCH, CONFIG)
    # 1.5 deg of pan, 1 deg of tilt and 8 % of f off: 20-35 px from the markings, a poor score.
    off = Hypothesis(truth.position_m, truth.pan_rad + math.radians(1.5), truth.tilt_rad - math.radians(1.0),
                     truth.focal_px * 1.08, 0.0)
    off.cost = float(scorer.costs(off.position_w, [off.pan_rad], [off.tilt_rad], [off.focal_px],
                                  CONFIG.score_hit_px, CONFIG.score_point_px)[0])
    far_away = Hypothesis(truth.position_m, truth.pan_rad + math.radians(40.0), truth.tilt_rad, truth.focal_px, -0.01)
    assert off.cost > -0.5
    polished = polish_locally([off, far_away], scorer, replace(CONFIG, local_polish_top_k=1), W)
    assert polished[1] is far_away  # only the best local_polish_top_k are moved
    moved = polished[0]
    assert moved.cost < -0.9
    assert abs(math.degrees(moved.pan_rad - truth.pan_rad)) < 0.1
    assert abs(math.degrees(moved.tilt_rad - truth.tilt_rad)) < 0.1
    assert moved.focal_px == pytest.approx(truth.focal_px, rel=0.01)
    assert polish_locally([off], scorer, replace(CONFIG, local_polish_top_k=0), W) == [off]
