"""Grass on both sides of a marking ridge (detect/ridge_sides.py), on maps drawn here, and through the detector's
ridges: a line on grass keeps its points, a bright seam between coloured blocks does not."""

from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.detect.ridge_sides import grass_beside
from broadtrack_graph.detect.ridges import marking_ridges
from broadtrack_graph.detect.weightfree import WeightFreeDetector
from broadtrack_graph.detect.weightfree_config import WeightFreeConfig

W, H = 200, 120


def _horizontal_ridge(half_width: int, grass_above: bool, grass_below: bool):
    """Points along y = 60 with normals (0, 1), the candidate run 2 * half_width + 1 rows, and the grass map."""
    candidates = np.zeros((H, W), np.uint8)
    candidates[60 - half_width:61 + half_width] = 1
    grass = np.zeros((H, W), np.uint8)
    if grass_above:
        grass[:60 - half_width] = 255
    if grass_below:
        grass[61 + half_width:] = 255
    points = np.column_stack([np.arange(20.0, 180.0), np.full(160, 60.0)])
    normals = np.tile([0.0, 1.0], (160, 1))
    return points, normals, candidates, grass


def test_a_line_with_grass_on_both_sides_keeps_every_point_whatever_its_width():
    for half_width in (0, 1, 4, 8):  # up to a 17 px run: the grass is read past the run's edge
        assert grass_beside(*_horizontal_ridge(half_width, True, True), margin_px=2.0).all()


def test_a_ridge_with_grass_on_one_side_or_none_is_dropped():
    for above, below in ((True, False), (False, True), (False, False)):
        assert not grass_beside(*_horizontal_ridge(1, above, below), margin_px=2.0).any()


def test_a_side_beyond_the_image_or_a_run_wider_than_the_reach_is_not_held_against_a_point():
    points, normals, candidates, grass = _horizontal_ridge(1, True, False)
    near_edge = np.column_stack([np.arange(20.0, 180.0), np.full(160, H - 2.0)])  # below: off the image at once
    candidates[H - 3:] = 1
    grass[:H - 3] = 255
    assert grass_beside(near_edge, normals, candidates, grass, margin_px=2.0).all()
    wide = np.zeros((H, W), np.uint8)
    wide[30:91] = 1  # no edge within 12 px of the centre either way
    assert grass_beside(points, normals, wide, np.zeros((H, W), np.uint8), margin_px=2.0, reach_px=12).all()
    assert len(grass_beside(np.zeros((0, 2)), np.zeros((0, 2)), candidates, grass, 2.0)) == 0


def test_the_detector_keeps_a_painted_line_and_drops_a_seam_between_two_coloured_blocks():
    config = WeightFreeConfig()
    detector = WeightFreeDetector(config=config)
    grey = np.full((H, W), 90, np.uint8)
    cv2.line(grey, (0, 55), (199, 63), 160, 3, cv2.LINE_AA)  # a line about 3 px wide on grass, slanted ...
    grey[:, 140:] = 60  # ... and right of x = 140 two dark blocks with a bright seam between them
    cv2.line(grey, (140, 84), (199, 88), 160, 3, cv2.LINE_AA)
    grass = np.zeros((H, W), np.uint8)
    grass[:, :140] = 255
    allowed = np.full((H, W), 255, np.uint8)
    args = (grey, allowed, None, detector._tophat_kernel, detector._ridge_kernel, config, False)
    before, _, _ = marking_ridges(*args)
    after, _, _ = marking_ridges(*args, grass)
    seam = lambda p: (p[:, 0] > 150) & (np.abs(p[:, 1] - (84 + (p[:, 0] - 140) * 4 / 59)) < 2)  # noqa: E731
    line = lambda p: (p[:, 0] > 10) & (p[:, 0] < 130) & (np.abs(p[:, 1] - (55 + p[:, 0] * 8 / 199)) < 2)  # noqa: E731
    assert seam(before).sum() > 30 and seam(after).sum() <= 0.1 * seam(before).sum()  # a few without a normal
    assert line(after).sum() == line(before).sum() > 100
    off = marking_ridges(*args[:5], WeightFreeConfig(side_margin_px=0.0), False, grass)[0]
    assert len(off) == len(before)  # 0: not tested
