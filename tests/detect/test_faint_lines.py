"""Faint straight markings found by their length (detect/faint_lines.py), on grass drawn here: a textured green
whose top-hat reaches 6 grey levels at its 90th percentile, and lines a few levels over it."""

from __future__ import annotations

from dataclasses import replace

import cv2
import numpy as np

from broadtrack_graph.detect.faint_lines import (
    FaintLineConfig,
    at_factor,
    candidate_lines,
    faint_line_points,
    shown_stretches,
    unknown_map,
)
from broadtrack_graph.detect.weightfree import WeightFreeDetector
from broadtrack_graph.detect.weightfree_config import WeightFreeConfig

W, H = 480, 270
SLOPE, CROSSING = 0.25, 130.0  # the line drawn: y = CROSSING + SLOPE (x - W / 2)


def _grass(seed: int = 0) -> np.ndarray:
    """(H, W, 3) float BGR grass with a fine texture (the same in the three levels)."""
    noise = cv2.GaussianBlur(np.random.default_rng(seed).normal(0, 6.0, (H, W)).astype(np.float32), (0, 0), 0.8)
    return np.dstack([40 + noise, 110 + noise, 50 + noise])


def _with_line(image: np.ndarray, level: float, colour=(1.0, 1.0, 1.0), width_px: float = 2.0) -> np.ndarray:
    """``image`` with the line drawn ``level`` grey levels bright (times ``colour`` in each level), antialiased."""
    rows, cols = np.mgrid[0:H, 0:W].astype(float)
    distance = np.abs(rows - (CROSSING + SLOPE * (cols - W / 2))) / np.hypot(1.0, SLOPE)
    cover = np.clip(width_px / 2 + 0.5 - distance, 0.0, 1.0)
    return image + level * np.asarray(colour)[None, None, :] * cover[..., None]


def _faint(image: np.ndarray, known=np.zeros((0, 2)), allowed=None, config=FaintLineConfig()) -> np.ndarray:
    detector = WeightFreeDetector()
    allowed = np.full((H, W), 255, np.uint8) if allowed is None else allowed
    return faint_line_points(np.clip(image, 0, 255).astype(np.uint8), allowed, known, detector._tophat_kernel,
                             detector._ridge_kernel, detector.config, config)


def _off_line_px(points: np.ndarray) -> np.ndarray:
    return np.abs(points[:, 1] - (CROSSING + SLOPE * (points[:, 0] - W / 2))) / np.hypot(1.0, SLOPE)


def test_a_line_a_few_levels_over_the_texture_is_found_along_its_length_and_grass_alone_gives_nothing():
    grey = cv2.cvtColor(np.clip(_grass(), 0, 255).astype(np.uint8), cv2.COLOR_BGR2GRAY)
    tophat = cv2.morphologyEx(grey, cv2.MORPH_TOPHAT, WeightFreeDetector()._tophat_kernel)
    assert 5 <= np.percentile(tophat, 90) <= 7  # the texture the ridge detector's threshold has to clear
    assert len(_faint(_grass())) == 0
    for level in (8.0, 12.0):  # under the ridge detector's 14 levels (and the texture's 90th percentile plus 4)
        points = _faint(_with_line(_grass(), level))
        off = _off_line_px(points)
        assert np.count_nonzero(off < 1.0) >= 0.9 * len(points)
        # Most of the line's length (it crosses the image, about 490 px) is found.
        along = np.unique(np.round(points[off < 1.0, 0]))
        assert len(along) > 0.8 * W


def test_a_line_smeared_wide_and_faint_is_found_at_a_coarser_scale_and_on_it():
    # A soft, low-resolution camera spreads a 2 px line over 8 px: 6 levels over grass with sensor noise, a band the
    # working size's step does not see as a line.
    for seed in (3, 5, 7):
        noisy = _grass(seed) + np.random.default_rng(seed + 1).normal(0, 3.0, (H, W, 1))
        smeared = _with_line(noisy, 6.0, width_px=8.0)
        assert len(_faint(smeared, config=replace(FaintLineConfig(), coarse_factors=()))) == 0
        points = _faint(smeared)
        off = _off_line_px(points)
        # Found along a good part of its length, at its centre to within a coarse pixel, and nothing else.
        assert len(points) >= 100 and np.count_nonzero(off < 2.0) >= 0.75 * len(points)
        assert len(np.unique(np.round(points[off < 2.0, 0]))) > 0.25 * W
        assert np.median(off[off < 2.0]) < 1.0
        assert len(_faint(noisy)) == 0


def test_at_factor_divides_the_counts_and_lengths_along_a_line_down_to_the_floor():
    config = FaintLineConfig()
    assert at_factor(config, 1) is config
    half = at_factor(config, 2)
    assert (half.min_votes, half.min_new_votes, half.min_run_px, half.window_px) == (15, 10, 30, 7)
    third = at_factor(config, 3)
    assert (third.min_votes, third.min_new_votes, third.min_run_px, third.window_px) == (10, 8, 20, 7)
    assert third.min_z == config.min_z  # the significance asked of a line is the same at every scale


def test_coloured_lines_and_the_markings_already_found_are_left_alone():
    # A yellow line (no blue): as bright in the grey level, not in the least of the three.
    assert len(_faint(_with_line(_grass(), 12.0, colour=(0.0, 1.0, 1.0)))) == 0
    # The line's left half already found: only its right half is added.
    xs = np.arange(0.0, W / 2, 1.0)
    known = np.column_stack([xs, CROSSING + SLOPE * (xs - W / 2)])
    points = _faint(_with_line(_grass(), 12.0), known=known)
    assert len(points) and points[:, 0].min() > W / 2 - 6
    # Nor where markings may not be.
    allowed = np.full((H, W), 255, np.uint8)
    allowed[:, W // 2:] = 0
    points = _faint(_with_line(_grass(), 12.0), allowed=allowed)
    assert len(points) and points[:, 0].max() < W / 2


def test_a_step_of_light_is_not_a_line():
    image = _grass()
    image[:, :W // 2] += 15.0  # a mown stripe's edge down the middle
    assert len(_faint(image)) == 0


def test_candidate_lines_recover_a_line_from_its_points_among_scattered_ones():
    rng = np.random.default_rng(1)
    xs = np.arange(20.0, 460.0, 1.5)
    on_line = np.column_stack([xs, CROSSING + SLOPE * (xs - W / 2)]) + rng.normal(0, 0.3, (len(xs), 2))
    normal = np.array([-SLOPE, 1.0]) / np.hypot(1.0, SLOPE)
    scattered = rng.uniform([0, 0], [W, H], (3000, 2))
    angles = rng.uniform(0, np.pi, 3000)
    points = np.vstack([on_line, scattered])
    normals = np.vstack([np.tile(normal, (len(xs), 1)), np.column_stack([np.cos(angles), np.sin(angles)])])
    lines = candidate_lines(points, normals, np.ones((H, W), np.uint8), FaintLineConfig())
    assert len(lines) >= 1
    angle, distance = lines[0]
    expected_angle = np.arctan2(normal[1], normal[0]) % np.pi
    assert abs(angle - expected_angle) < np.radians(1.5)
    # The line's distance from the origin along its normal.
    assert abs(distance - (normal[0] * W / 2 + normal[1] * CROSSING)) < 2.0
    # The scattered points alone agree on no line.
    assert len(candidate_lines(scattered, normals[len(xs):], np.ones((H, W), np.uint8), FaintLineConfig())) == 0


def test_a_candidate_a_degree_off_is_fitted_onto_its_line_before_it_is_traced():
    image = np.clip(_with_line(_grass(), 12.0), 0, 255).astype(np.uint8)
    tophat = cv2.morphologyEx(np.min(image, axis=2), cv2.MORPH_TOPHAT, WeightFreeDetector()._tophat_kernel)
    normal = np.array([-SLOPE, 1.0]) / np.hypot(1.0, SLOPE)
    angle = np.arctan2(normal[1], normal[0]) + np.radians(1.0)  # a Hough bin away
    distance = np.cos(angle) * W / 2 + np.sin(angle) * CROSSING  # through the line's middle
    points = shown_stretches(tophat, np.ones((H, W), np.uint8), np.array([[angle, distance]]), FaintLineConfig())
    # Unfitted, the line would leave its ridge 1.5 px from the middle and be traced over a fifth of the image.
    assert len(np.unique(np.round(points[:, 0]))) > 0.8 * W
    assert np.percentile(_off_line_px(points), 95) < 0.5


def test_unknown_map_clears_a_square_round_each_known_point():
    cleared = unknown_map(np.array([[10.2, 20.7]]), (40, 30), 3)
    assert cleared.shape == (30, 40) and cleared.dtype == np.uint8
    assert cleared[21, 10] == 0 and cleared[18, 7] == 0 and cleared[24, 13] == 0
    assert cleared[21, 14] == 1 and cleared[17, 10] == 1
    assert unknown_map(np.zeros((0, 2)), (40, 30), 3).all()


def test_the_faint_look_adds_the_faint_line_to_the_markings_found_and_keeps_what_it_was_taken_of():
    image = np.clip(_with_line(_grass(), 10.0), 0, 255).astype(np.uint8)
    detector = WeightFreeDetector()
    found = detector.find_markings(image)
    assert len(detector.name(found).marking_points_px) < 10  # the ridge detector alone misses it
    looked = detector.with_faint_lines(found)
    points = detector.name(looked).marking_points_px
    assert len(points) > 50 and np.median(_off_line_px(points)) < 1.0
    assert looked.faint_look_of is found and looked.faint is None
    assert detector.with_faint_lines(looked) is looked  # taken once
    assert looked.unnamed.marking_mask.sum() == len(looked.points_work_px) > len(found.points_work_px)
    assert looked.faint_points_added == len(looked.points_work_px) - len(found.points_work_px)
    assert found.faint_points_added == 0
    # Not offered: the markings as they are.
    plain = WeightFreeDetector(config=WeightFreeConfig(faint_lines=None))
    unoffered = plain.find_markings(image)
    assert unoffered.faint is None and plain.with_faint_lines(unoffered) is unoffered


def test_the_faint_look_takes_the_coarser_scales_only_on_a_frame_read_as_blurred_or_smeared():
    # The frame is enlarged 2x to the working width: the 4 px band is 8 px wide there, as in the test above.
    noisy = _grass(3) + np.random.default_rng(4).normal(0, 3.0, (H, W, 1))
    image = np.clip(_with_line(noisy, 6.0, width_px=4.0), 0, 255).astype(np.uint8)
    detector = WeightFreeDetector()
    found = detector.find_markings(image)
    assert not found.faint.coarse  # the grass is sharp: the band does not make the frame read as blurred
    assert detector.with_faint_lines(found).faint_points_added == 0
    blurred = replace(found, faint=replace(found.faint, coarse=True))
    points = detector.name(detector.with_faint_lines(blurred)).marking_points_px
    assert len(points) >= 50 and np.median(_off_line_px(points)) < 1.0
