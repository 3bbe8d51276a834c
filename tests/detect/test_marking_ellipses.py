"""Ellipses of the marking map (the images of the pitch's circles), on masks drawn here, and the distance to them."""

from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.detect.marking_ellipses import marking_ellipses
from broadtrack_graph.detect.marking_structures import marking_lines


def test_a_long_straight_marking_is_not_taken_for_a_flat_ellipse():
    # A 360p-like map: the near touchline and the board bases just below it, bent by the lens, lie on a
    # very flat ellipse with much more support than the small centre circle; the circle must come first.
    mask = np.zeros((540, 960), np.uint8)
    cv2.ellipse(mask, (480, 510), (470, 12), 0, 185, 355, 1, 1)
    cv2.ellipse(mask, (480, 510), (470, 12), 0, 5, 175, 1, 1)
    cv2.ellipse(mask, (480, 220), (140, 38), 0, 0, 150, 1, 1)
    cv2.ellipse(mask, (480, 220), (140, 38), 0, 170, 360, 1, 1)
    ellipses = marking_ellipses(mask.astype(bool), 960)
    assert ellipses, "no ellipse found"
    first = ellipses[0]
    assert np.linalg.norm(first.centre_px - (480, 220)) < 3
    assert abs(first.semi_axes_px[0] - 140) < 3 and abs(first.semi_axes_px[1] - 38) < 3
    assert all(e.semi_axes_px[1] / e.semi_axes_px[0] >= 0.06 for e in ellipses)


def test_an_arc_at_the_image_border_is_not_returned_as_an_ellipse():
    # A penalty arc whose circle lies mostly beyond the right edge: an ellipse fitted to that short arc has
    # poorly determined axes; a whole circle inside the image is kept.
    mask = np.zeros((540, 960), np.uint8)
    cv2.ellipse(mask, (1100, 300), (400, 90), 0, 120, 240, 1, 1)
    cv2.ellipse(mask, (300, 200), (140, 38), 0, 0, 360, 1, 1)
    ellipses = marking_ellipses(mask.astype(bool), 960)
    assert len(ellipses) >= 1
    assert all(np.linalg.norm(e.centre_px - (300, 200)) < 5 for e in ellipses), [e.centre_px for e in ellipses]
    # Asked for separately (the re-initialisation does when nothing else fits), the border arc is found.
    border = marking_ellipses(mask.astype(bool), 960, at_border=True)
    assert len(border) == 1 and np.linalg.norm(border[0].centre_px - (1100, 300)) < 15


def test_an_arc_meeting_its_line_is_found_once_the_pieces_are_cut_along_the_line():
    """A penalty arc's image (half an ellipse) whose ends touch a long straight marking: one piece with it, no ellipse;
    cut along the line (ellipse_cut_line_px), the arc's ellipse."""
    from broadtrack_graph.detect.marking_structures import MarkingStructureConfig

    mask = np.zeros((540, 960), np.uint8)
    centre, axes = (480, 300), (260, 110)
    cv2.ellipse(mask, centre, axes, 0.0, 180.0, 360.0, 1, 1)  # the upper half, ends on y = 300
    cv2.line(mask, (20, 300), (940, 300), 1, 1)
    lines = marking_lines(mask > 0, 960)
    assert not marking_ellipses(mask > 0, 960, MarkingStructureConfig(ellipse_min_coverage=0.3), lines=lines)
    cut = MarkingStructureConfig(ellipse_min_coverage=0.3, ellipse_cut_line_px=160.0)
    found = marking_ellipses(mask > 0, 960, cut, lines=lines)
    assert found
    np.testing.assert_allclose(found[0].centre_px, centre, atol=4.0)
    np.testing.assert_allclose(found[0].semi_axes_px, axes, atol=6.0)


def test_many_ellipses_distances_in_one_pass_are_each_ellipses_own():
    """A circle of radius R = 50 px: a point rho from its centre is (rho^2 - R^2) / (2 rho) from it to first order
    (negative inside); an ellipse's distances among several at once are, bit for bit, those it gives alone."""
    from broadtrack_graph.detect.marking_ellipses import ImageEllipse, signed_distances_to_ellipses

    points = np.array([[160.0, 100.0], [100.0, 130.0], [100.0, 100.0 - 60.0]])
    circle = ((100.0, 100.0), (50.0, 50.0), 0.3)
    rho = np.array([60.0, 30.0, 60.0])
    assert np.allclose(signed_distances_to_ellipses([circle], points)[0], (rho**2 - 50.0**2) / (2 * rho), atol=1e-9)
    rng = np.random.default_rng(4)
    ellipses = [(rng.uniform(0, 900, 2), tuple(sorted(rng.uniform(5, 400, 2), reverse=True)), rng.uniform(0, 3.1))
                for _ in range(6)]
    many = rng.uniform(-200, 1100, (300, 2))
    together = signed_distances_to_ellipses(ellipses, many)
    for row, (centre, axes, angle) in zip(together, ellipses):
        assert np.array_equal(row, ImageEllipse(np.asarray(centre), axes, angle, 0.0).signed_distances_px(many))
