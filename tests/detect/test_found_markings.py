"""The markings found before a camera is known: the players' legs found when the detections are first read."""

from __future__ import annotations

import pickle

import numpy as np
from drawn_frames import draw_frame

from broadtrack_graph.detect.player_feet import boxes_to_the_feet, with_legs
from broadtrack_graph.detect.weightfree import WeightFreeDetector
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate

W, H = 640, 360
PITCH = PitchTemplate()


def _found():
    camera = Camera.from_degrees(700.0, 0.0, -8.0, 74.0, 0.0, (0.0, 55.0, -12.0), W, H)
    image, _ = draw_frame(camera, players=14)
    detector = WeightFreeDetector(PITCH)
    return detector, image, detector.find_markings(image)


def test_the_players_run_down_their_legs_when_the_detections_are_first_read():
    detector, image, found = _found()
    bodies = found.bodies
    assert bodies is not None and len(bodies.boxes_work_px) >= 8
    # Until read, the detections hold the bodies; read, the boxes run on down the legs and the mask takes them.
    assert np.array_equal(found.detections.player_boxes_px, bodies.boxes_work_px / found.scale)
    feet = boxes_to_the_feet(bodies.boxes_work_px, bodies.grey, bodies.grass, detector.config.feet_contrast,
                             detector.config.feet_max_share)
    assert np.array_equal(found.unnamed.player_boxes_px, feet / found.scale)
    assert np.any(feet[:, 3] > bodies.boxes_work_px[:, 3])  # some legs below the bodies
    legs = with_legs(bodies.body_mask, bodies.boxes_work_px, feet, detector.config.player_margin_px) > 0
    assert np.array_equal(found.unnamed.player_mask, legs)
    assert np.count_nonzero(legs) > np.count_nonzero(bodies.body_mask)
    # The rest of the detections is the same before and after.
    for name in ("marking_mask", "marking_points_px", "field_mask"):
        assert np.array_equal(getattr(found.unnamed, name), getattr(found.detections, name))
    # Naming reads them: detect() is find_markings() then name(), with the legs.
    detected = detector.detect(image)
    assert np.array_equal(detected.player_boxes_px, found.unnamed.player_boxes_px)
    assert np.array_equal(detected.player_mask, found.unnamed.player_mask)


def test_a_copy_read_before_it_was_sent_carries_the_legs_and_one_not_read_finds_them_itself():
    _, _, found = _found()
    fresh = pickle.loads(pickle.dumps(found))  # sent unread: the other side finds the legs
    assert "unnamed" not in vars(fresh)
    expected = found.unnamed  # read here: kept, and a copy sent now carries it
    sent = pickle.loads(pickle.dumps(found))
    assert "unnamed" in vars(sent)
    for copy in (fresh, sent):
        assert np.array_equal(copy.unnamed.player_mask, expected.player_mask)
        assert np.array_equal(copy.unnamed.player_boxes_px, expected.player_boxes_px)
