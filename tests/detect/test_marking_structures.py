"""Structures of the marking map: straight markings (greedy Hough), and with them an ellipse, on masks drawn here."""

from __future__ import annotations

import math

import cv2
import numpy as np

from broadtrack_graph.detect.marking_ellipses import marking_ellipses
from broadtrack_graph.detect.marking_structures import _sorted_percentile, marking_lines


def test_marking_lines_finds_the_drawn_lines_not_the_specks():
    mask = np.zeros((540, 960), np.uint8)
    drawn = [((40, 100), (900, 140)), ((300, 520), (620, 60)), ((100, 400), (500, 420))]
    for a, b in drawn:
        cv2.line(mask, a, b, 1, 1)
    rng = np.random.default_rng(4)
    for x, y in rng.integers([0, 0], [960, 540], size=(60, 2)):  # grass specks: 2 px each
        mask[y, x: x + 2] = 1
    lines = marking_lines(mask > 0, 1920)  # frame twice the map's width
    assert len(lines) == 3
    for a, b in drawn:
        a2, b2 = 2 * np.array(a, float), 2 * np.array(b, float)
        best = min(lines, key=lambda line: abs(line.normal @ a2 + line.offset_px)
                   + abs(line.normal @ b2 + line.offset_px))
        assert abs(best.normal @ a2 + best.offset_px) < 3.0 and abs(best.normal @ b2 + best.offset_px) < 3.0
        assert 0.6 * np.linalg.norm(b2 - a2) < best.support_px < 1.3 * np.linalg.norm(b2 - a2)


def test_a_lines_extent_is_numpys_percentile_of_its_sorted_support():
    # The extent's 10th and 90th percentiles, read off the sorted support, to the last bit of np.percentile's.
    rng = np.random.default_rng(7)
    for trial in range(400):
        values = np.sort(rng.normal(0.0, 300.0, int(rng.integers(1, 300))).astype((np.float32, np.float64)[trial % 2]))
        assert (_sorted_percentile(values, 0.1), _sorted_percentile(values, 0.9)) == tuple(
            np.percentile(values, [10.0, 90.0]))


def test_marking_structures_recover_two_drawn_lines_and_an_ellipse():
    """Two long lines at the top, an ellipse (a centre circle seen from the stand) below; map 960 wide, frame 1920."""
    mask = np.zeros((540, 960), np.uint8)
    drawn = [((30, 40), (930, 90)), ((60, 200), (420, 130))]
    for a, b in drawn:
        cv2.line(mask, a, b, 1, 1)
    centre, axes = (500, 380), (220, 90)  # semi-axes a >= b, major axis level
    cv2.ellipse(mask, centre, axes, 0.0, 0.0, 360.0, 1, 1)
    lines = marking_lines(mask > 0, 1920)
    assert len(lines) >= 2
    for a, b in drawn:  # each drawn line is one of the two strongest, both ends within 2 frame pixels
        a2, b2 = 2 * np.array(a, float), 2 * np.array(b, float)
        best = min(lines[:2], key=lambda line: abs(line.normal @ a2 + line.offset_px))
        assert abs(best.normal @ a2 + best.offset_px) < 2.0 and abs(best.normal @ b2 + best.offset_px) < 2.0
        np.testing.assert_allclose(np.linalg.norm(best.direction), 1.0)
    ellipses = marking_ellipses(mask > 0, 1920)
    assert len(ellipses) >= 1
    found = ellipses[0]
    np.testing.assert_allclose(found.centre_px, 2 * np.array(centre, float), atol=2.0)
    np.testing.assert_allclose(found.semi_axes_px, 2 * np.array(axes, float), atol=4.0)  # 2 px at the map's width
    assert abs(math.sin(found.angle_rad)) < 0.02
    # Points on the drawn ellipse (frame pixels) are within a pixel or two of it; the centre is not.
    t = np.linspace(0.0, 2 * math.pi, 50)
    on = 2 * np.column_stack([centre[0] + axes[0] * np.cos(t), centre[1] + axes[1] * np.sin(t)])
    assert found.distances_px(on).max() < 3.0
    assert found.distances_px(2 * np.array([centre], float))[0] > 100.0


def test_a_hatch_does_not_crowd_the_markings_out_of_the_lines_kept():
    """A goal net's strands (12 parallel lines 12 px apart, 400 px long) and two shorter markings; 4 lines kept: with
    candidate_lines the strands are dropped (the two at the hatch's edges, with fewer neighbours, may stay) and both
    markings kept, without it the strands take the places."""
    from broadtrack_graph.detect.marking_structures import MarkingStructureConfig

    mask = np.zeros((540, 960), np.uint8)
    for k in range(12):
        cv2.line(mask, (300, 200 + 12 * k), (700, 206 + 12 * k), 1, 1)
    markings = [((20, 40), (260, 60)), ((60, 520), (260, 420))]
    for a, b in markings:
        cv2.line(mask, a, b, 1, 1)
    config = MarkingStructureConfig(max_lines=4)

    def kept(lines):
        return [any(abs(line.normal @ np.array(a, float) + line.offset_px) < 2.0
                    and abs(line.normal @ np.array(b, float) + line.offset_px) < 2.0 for line in lines)
                for a, b in markings]

    assert all(kept(marking_lines(mask > 0, 960, MarkingStructureConfig(max_lines=4, candidate_lines=24))))
    assert len(marking_lines(mask > 0, 960, MarkingStructureConfig(max_lines=4, candidate_lines=24))) <= 4
    assert not all(kept(marking_lines(mask > 0, 960, config)))
