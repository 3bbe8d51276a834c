"""Players' blobs apart from the markings they stand on: masks and frames drawn here."""

from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.detect.player_blobs import bodies_apart_from_markings
from broadtrack_graph.detect.weightfree import WeightFreeDetector
from broadtrack_graph.geometry.pitch import PitchTemplate


def _body(mask: np.ndarray, centre=(100, 80), axes=(8, 24)) -> np.ndarray:
    cv2.ellipse(mask, centre, axes, 0, 0, 360, 255, -1)
    return mask


def test_a_long_marking_through_a_body_is_cut_off_and_its_legs_stay():
    blobs = _body(np.zeros((240, 200), np.uint8))
    cv2.line(blobs, (20, 60), (190, 120), 255, 3)  # a marking 3 px wide, the body 17 px wide
    cv2.line(blobs, (96, 100), (94, 118), 255, 2)  # a leg below the body
    cv2.line(blobs, (104, 100), (106, 118), 255, 2)
    out = bodies_apart_from_markings(blobs)
    assert out[80, 100] == 255 and out[112, 95] == 255 and out[112, 105] == 255  # the body and its legs
    assert not out[:, :60].any() and not out[:, 150:].any()  # the marking away from the body
    # Near the body, within its half width, the marking stays with it (the player hides it there).
    assert out[:, 60:150].sum() < blobs[:, 60:150].sum()


def test_a_marking_alone_and_a_body_alone_are_not_changed():
    line = np.zeros((120, 200), np.uint8)
    cv2.line(line, (10, 20), (190, 100), 255, 3)
    assert np.array_equal(bodies_apart_from_markings(line), line)
    body = _body(np.zeros((160, 200), np.uint8))
    assert np.array_equal(bodies_apart_from_markings(body), body)
    empty = np.zeros((10, 10), np.uint8)
    assert np.array_equal(bodies_apart_from_markings(empty), empty)


def test_a_player_standing_on_a_wide_marking_is_found_and_the_marking_beyond_it_too():
    # A zoomed view at the working width: a line 6 px wide (wider than the players' opening removes), a player's body
    # standing on it. As one blob they were too tall and narrow for a player: the player was not found.
    rng = np.random.default_rng(0)
    image = np.clip(np.full((540, 960, 3), (40, 140, 60), np.float32) + rng.normal(0, 2, (540, 960, 3)), 0, 255)
    image = image.astype(np.uint8)
    image[:60] = (40, 40, 40)  # a stand above the pitch
    cv2.line(image, (440, 150), (470, 420), (235, 235, 235), 6, cv2.LINE_AA)
    cv2.ellipse(image, (452, 200), (16, 48), 0, 0, 360, (40, 20, 150), -1, cv2.LINE_AA)
    detections = WeightFreeDetector(PitchTemplate()).detect(image)
    assert len(detections.player_boxes_px) == 1
    x0, y0, x1, y1 = detections.player_boxes_px[0]
    assert x1 - x0 < 50 and 140 <= y0 <= 160  # the body's width, from its top
    points = detections.marking_points_px
    beyond = points[(points[:, 1] > 260) & (points[:, 1] < 410)]  # below the body (248), short of the line's end
    on_line = np.abs(beyond[:, 0] - (440 + 30 * (beyond[:, 1] - 150) / 270))
    assert len(beyond) > 30 and np.all(on_line < 3)
