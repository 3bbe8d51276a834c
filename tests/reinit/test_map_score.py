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


def test_best_distinct_compares_pans_round_the_circle():
    # 179.9 and -179.9 deg are 0.2 deg apart (3.5 px at f = 1000): one view, not two
    pans = np.radians([179.9, -179.9, 90.0])
    costs = np.array([-0.9, -0.8, -0.5])
    assert best_distinct(pans, np.zeros(3), np.full(3, 1000.0), costs, 3, 5.0, 960) == [0, 2]


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


def test_polished_side_by_side_as_one_by_one_to_the_bit():
    truth = Camera.from_degrees(1300.0, 0.0, 9.0, 77.0, 0.0, (0.0, 55.0, -12.0), W, H)
    mask, points = _drawn_map(truth)
    scorer = MapScorer(mask, points, (W, H), PITCH, CONFIG)
    rng = np.random.default_rng(8)
    hypotheses = []
    for position in ((0.0, 55.0, -12.0), (0.0, 55.0, -12.0), (3.0, 60.0, -15.0), (0.0, 55.0, -12.0)):
        pan = truth.pan_rad + math.radians(rng.uniform(-3, 3))
        tilt, focal = truth.tilt_rad + math.radians(rng.uniform(-2, 2)), truth.focal_px * rng.uniform(0.9, 1.1)
        cost = float(scorer.costs(position, [pan], [tilt], [focal], CONFIG.score_hit_px, CONFIG.score_point_px)[0])
        hypotheses.append(Hypothesis(np.array(position), pan, tilt, focal, cost))
    polished = polish_locally(hypotheses, scorer, CONFIG, W)
    # The reference: each hypothesis's pattern search on its own, one score call per step.
    grid = np.array(np.meshgrid([-1.0, 0.0, 1.0], [-1.0, 0.0, 1.0], [-1.0, 0.0, 1.0], indexing="ij")).reshape(3, -1)
    chosen = best_distinct(*(np.array([getattr(h, name) for h in hypotheses]) for name in ("pan_rad", "tilt_rad",
                                                                                         "focal_px", "cost")),
                           CONFIG.local_polish_top_k, CONFIG.distinct_per_width * W, W)
    assert len(chosen) >= 3
    for k, (h, got) in enumerate(zip(hypotheses, polished)):
        if k not in chosen:
            assert got is h
            continue
        pan, tilt, focal, cost = h.pan_rad, h.tilt_rad, h.focal_px, h.cost
        step_px = CONFIG.local_polish_step_per_width * W
        while step_px >= CONFIG.local_polish_min_step_per_width * W:
            angle, factor = step_px / focal, 1.0 + step_px / (W / 2.0)
            pans, tilts, focals = pan + grid[0] * angle, tilt + grid[1] * angle, focal * factor ** grid[2]
            costs = scorer.costs(h.position_w, pans, tilts, focals, CONFIG.score_hit_px, CONFIG.score_point_px)
            j = int(np.argmin(costs))
            if costs[j] < cost - 1e-9:
                pan, tilt, focal, cost = float(pans[j]), float(tilts[j]), float(focals[j]), float(costs[j])
            else:
                step_px /= 2.0
        assert (got.pan_rad, got.tilt_rad, got.focal_px, got.cost) == (pan, tilt, focal, cost)
        np.testing.assert_array_equal(got.position_w, h.position_w)
    assert sum(got.cost < h.cost for h, got in zip(hypotheses, polished)) >= 3


def test_the_plane_score_of_a_camera_s_ground_homography_is_the_camera_s_score():
    truth = Camera.from_degrees(1300.0, 0.0, 9.0, 77.0, 0.0, (0.0, 55.0, -12.0), W, H)
    mask, points = _drawn_map(truth)
    scorer = MapScorer(mask, points, (W, H), PITCH, CONFIG)
    cameras = [truth, truth.replace(pan_rad=truth.pan_rad + math.radians(1.0)),
               truth.replace(focal_px=1.1 * truth.focal_px)]
    K = np.array([[truth.focal_px, 0.0, W / 2], [0.0, truth.focal_px, H / 2], [0.0, 0.0, 1.0]])
    H_px = []
    for camera in cameras:
        K[0, 0] = K[1, 1] = camera.focal_px
        R, t = camera.R_cw, -camera.R_cw @ camera.position_m
        H_px.append(K @ np.column_stack([R[:, 0], R[:, 1], t]))  # (x, y, 1) -> pixels, third row the depth
    H_px = np.array(H_px + [-H_px[0]])  # the last: the same camera with the homography's sign flipped
    sign = np.array([1.0, 1.0, 1.0, -1.0])
    focal = np.array([c.focal_px for c in cameras] + [truth.focal_px])
    costs = scorer.plane_costs(H_px, sign, focal, CONFIG.score_hit_px, CONFIG.score_point_px, chunk=3)
    for camera, cost in zip(cameras, costs):
        assert scorer.camera_cost(camera, CONFIG.score_hit_px, CONFIG.score_point_px) == pytest.approx(cost, abs=0.02)
    assert costs[0] < -0.9 and costs[0] < costs[1] and costs[0] < costs[2]
    assert costs[3] == costs[0]  # a homography's scale, sign included, does not change the score
    behind = scorer.plane_costs(H_px[:1], -sign[:1], focal[:1], CONFIG.score_hit_px, CONFIG.score_point_px)
    assert behind[0] == math.inf  # the template behind the camera: nothing in the image
    coarse = scorer.plane_costs(H_px, sign, focal, CONFIG.score_hit_px, CONFIG.score_point_px, thin=2)
    assert coarse == pytest.approx(costs, abs=0.05)


def test_the_best_plane_costs_are_those_of_every_cost():
    # Asked for the best few only, the scorer reads the precision only of the homographies whose recall could put
    # them among those: the best few are the same numbers, the others inf or no better than the worst of them.
    truth = Camera.from_degrees(1300.0, 0.0, 9.0, 77.0, 0.0, (0.0, 55.0, -12.0), W, H)
    mask, points = _drawn_map(truth)
    scorer = MapScorer(mask, points, (W, H), PITCH, CONFIG)
    rng = np.random.default_rng(3)
    cameras = [truth.replace(pan_rad=truth.pan_rad + math.radians(rng.normal(0, 4)),
                             tilt_rad=truth.tilt_rad + math.radians(rng.normal(0, 2)),
                             focal_px=truth.focal_px * math.exp(rng.normal(0, 0.2))) for _ in range(300)]
    H_px, focal = [], []
    for camera in cameras:
        K = np.array([[camera.focal_px, 0.0, W / 2], [0.0, camera.focal_px, H / 2], [0.0, 0.0, 1.0]])
        R, t = camera.R_cw, -camera.R_cw @ camera.position_m
        H_px.append(K @ np.column_stack([R[:, 0], R[:, 1], t]))
        focal.append(camera.focal_px)
    H_px, sign, focal = np.array(H_px), np.ones(len(cameras)), np.array(focal)
    every = scorer.plane_costs(H_px, sign, focal, CONFIG.coarse_hit_px, CONFIG.coarse_point_px, chunk=64, thin=2)
    for best in (1, 10, 64):
        some = scorer.plane_costs(H_px, sign, focal, CONFIG.coarse_hit_px, CONFIG.coarse_point_px, chunk=64, thin=2,
                                  best=best)
        top = np.argsort(every, kind="stable")[:best]
        np.testing.assert_array_equal(some[top], every[top])
        read = np.isfinite(some)
        np.testing.assert_array_equal(some[read], every[read])
        assert np.all(every[~read] >= every[top].max())
    assert np.isfinite(every).sum() > 100
    some = scorer.plane_costs(H_px, sign, focal, CONFIG.coarse_hit_px, CONFIG.coarse_point_px, chunk=64, thin=2,
                              best=10)
    assert (~np.isfinite(some)).sum() > 100  # most were not read
