"""Player boxes down to the feet (detect/player_feet.py), on frames drawn here and through the detector."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from broadtrack_graph.detect.player_feet import boxes_to_the_feet, with_legs
from broadtrack_graph.detect.weightfree import WeightFreeDetector
from broadtrack_graph.detect.weightfree_config import WeightFreeConfig
from broadtrack_graph.geometry.pitch import PitchTemplate

W, H = 640, 360
PITCH = PitchTemplate()


def _player_on_grass(legs_grey: int, shadow: bool = False, line_below: bool = False):
    """A 640x360 frame of grass with one player: a red body 10x24 px at (300, 150) over two legs 1 px wide and
    18 px long (``legs_grey``), a darker-grass shadow under the feet and a marking line 6 px below them if asked."""
    image = np.zeros((H, W, 3), np.uint8)
    image[:] = (40, 140, 50)
    if shadow:
        cv2.ellipse(image, (305, 193), (14, 4), 0, 0, 360, (25, 90, 32), -1)
    if line_below:
        cv2.line(image, (0, 198), (W - 1, 198), (235, 235, 235), 2)
    cv2.rectangle(image, (300, 150), (310, 174), (30, 30, 200), -1)
    for x in (302, 308):
        cv2.line(image, (x, 175), (x, 192), (legs_grey,) * 3, 1)
    return image


def test_a_player_box_ends_at_the_feet_not_at_the_knees():
    detector = WeightFreeDetector(PITCH, WeightFreeConfig(work_width_px=W))
    for legs_grey in (200, 15):  # light socks or skin, dark boots and socks
        for shadow, line_below in ((False, False), (True, False), (False, True)):
            boxes = detector.detect(_player_on_grass(legs_grey, shadow, line_below)).player_boxes_px
            assert len(boxes) == 1
            x0, y0, x1, y1 = boxes[0]
            assert y0 == pytest.approx(150, abs=2) and y1 == pytest.approx(193, abs=2), (legs_grey, shadow, line_below)
    # Without legs below it, a body's box is the body's.
    bare = _player_on_grass(140)
    bare[175:193, 300:311] = (40, 140, 50)
    assert detector.detect(bare).player_boxes_px[0][3] == pytest.approx(175, abs=2)



def test_the_legs_below_a_body_make_its_box_and_nothing_else_does():
    image = _player_on_grass(200, shadow=True, line_below=True)
    grey = cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)
    grass = cv2.inRange(cv2.cvtColor(image, cv2.COLOR_BGR2HSV), (30, 40, 30), (95, 255, 255))
    body = np.array([[300.0, 150.0, 311.0, 175.0]])
    assert boxes_to_the_feet(body, grey, grass)[0, 3] == pytest.approx(193, abs=1)
    assert np.array_equal(boxes_to_the_feet(body, grey, grass)[0, :3], body[0, :3])
    # Capped at max_share of the body's height; a box at the image's bottom edge stays.
    assert boxes_to_the_feet(body, grey, grass, max_share=0.4)[0, 3] == pytest.approx(175 + 10, abs=1)
    assert boxes_to_the_feet(np.array([[300.0, 330.0, 311.0, 360.0]]), grey, grass)[0, 3] == 360
    assert boxes_to_the_feet(np.zeros((0, 4)), grey, grass).shape == (0, 4)


def test_the_box_ends_at_the_first_gap_of_gap_rows_rows_without_a_leg():
    image = _player_on_grass(200)
    image[183, 300:311] = (40, 140, 50)  # one row of grass across both legs
    grey = cv2.cvtColor(image, cv2.COLOR_BGR2GRAY)
    grass = cv2.inRange(cv2.cvtColor(image, cv2.COLOR_BGR2HSV), (30, 40, 30), (95, 255, 255))
    body = np.array([[300.0, 150.0, 311.0, 175.0]])
    assert boxes_to_the_feet(body, grey, grass, gap_rows=1)[0, 3] == 183  # stops at the gap
    assert boxes_to_the_feet(body, grey, grass, gap_rows=2)[0, 3] == 193  # steps over it, ends below the feet
    assert boxes_to_the_feet(body, grey, grass, gap_rows=3)[0, 3] == 193
    # Legs down to the bottom of what is looked at: the box ends there.
    assert boxes_to_the_feet(body, grey, grass, max_share=0.5)[0, 3] == 175 + 13


def test_the_player_mask_takes_the_legs_and_the_confidence_leaves_them_out():
    # Light socks or skin below a body are thin bright ridges on grass, as a marking is: the player mask takes the
    # legs down to the feet (a stride wider than the body too), and the confidence counts no ridge under it. The
    # marking map keeps them (a marking running down the image under a player's feet would be taken for a leg).
    from broadtrack_graph.geometry.camera import Camera
    from broadtrack_graph.geometry.template import TemplateCurves
    from broadtrack_graph.reinit.confidence import confidence_parts

    detector = WeightFreeDetector(PITCH, WeightFreeConfig(work_width_px=W))
    image = _player_on_grass(200, line_below=True)
    cv2.line(image, (299, 180), (296, 192), (200, 200, 200), 1)  # a leg striding out beside the body
    found = detector.detect(image)
    rows, cols = np.nonzero(found.marking_mask)
    on_legs = (rows >= 176) & (rows <= 193) & (cols >= 294) & (cols <= 314)
    assert on_legs.sum() >= 10
    assert found.player_mask[176:194, 298:313].all() and not found.player_mask[197:].any()
    # Any camera: the legs' ridges are not marking pixels the template must explain.
    camera = Camera.from_degrees(500.0, 0.0, 0.0, 70.0, 0.0, (0.0, 60.0, -15.0), W, H)
    curves = TemplateCurves(PITCH)
    with_mask = confidence_parts(camera, found.marking_mask, curves, player_mask=found.player_mask)
    without = confidence_parts(camera, found.marking_mask, curves)
    assert with_mask["marking_pixels"] <= without["marking_pixels"] - on_legs.sum() // 2
    # The mask itself: the box below each body down to its feet, the margin wider; no legs found, nothing added.
    bodies = np.array([[300.0, 150.0, 311.0, 175.0]])
    legs_only = with_legs(np.zeros((H, W), np.uint8), bodies, bodies + [0, 0, 0, 18], 3)
    assert legs_only[172:197, 297:315].all() and not legs_only[:172].any() and not legs_only[:, :297].any()
    assert not with_legs(np.zeros((H, W), np.uint8), bodies, bodies, 3).any()


def test_the_grass_median_is_numpys():
    """The grass level below a box, from the histogram of its grey levels, is np.median's (even counts: the mean
    of the two middle values)."""
    from broadtrack_graph.detect.player_feet import _median_grey

    rng = np.random.default_rng(2)
    for size in (1, 2, 3, 10, 11, 400, 401):
        for _ in range(50):
            values = rng.integers(0, 256, size).astype(np.uint8)
            assert _median_grey(values) == float(np.median(values.astype(np.float32)))
