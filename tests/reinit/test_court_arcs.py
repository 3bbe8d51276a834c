"""Arc-and-chord hypotheses: a circle's short arc and the line across it, rectified under the camera model."""

from __future__ import annotations

import math

import cv2
import numpy as np
import pytest

from broadtrack_graph.detect.marking_ellipses import ImageEllipse
from broadtrack_graph.detect.marking_structures import ImageLine
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.court_arcs import CourtArcConfig, arc_line_homographies, arc_points
from broadtrack_graph.reinit.court_circle import pitch_circle_chords
from broadtrack_graph.reinit.court_lines import cameras_from_homographies, pixel_homographies

PITCH = PitchTemplate()
W, H = 1280, 720
CHORDS = pitch_circle_chords(PITCH)  # centre circle, right penalty arc, left penalty arc
FOCAL_RANGE_N = (0.9, 32.0)


def _behind_the_goal() -> Camera:
    """A camera 27 m up beside the right goal, looking down at the penalty arc and the 16.5 m line from 23 m off."""
    return Camera.from_degrees(1900.0, 0.0, -108.0, 40.0, 0.6, (54.0, -7.0, -27.0), W, H)


def _image_line(camera: Camera, a_w, b_w) -> ImageLine:
    """The straight marking from a_w to b_w (pitch metres) as the map's line finder returns it."""
    (a, b), _ = camera.project(np.array([[*a_w, 0.0], [*b_w, 0.0]]))
    direction = (b - a) / np.linalg.norm(b - a)
    normal = np.array([-direction[1], direction[0]])
    centre = (a + b) / 2
    half = np.linalg.norm(b - a) / 2
    return ImageLine(normal, -float(normal @ centre), centre, direction, (-half, half), 2 * half)


def _arc_px(camera: Camera, chord, degrees: float) -> np.ndarray:
    """The painted arc's image points (beyond the chord), ``degrees`` of it about its middle, frame pixels."""
    half = math.radians(degrees) / 2
    facing = math.pi if chord.chord_x_m < chord.centre_x_m else 0.0  # beyond the chord, away from the centre
    if abs(chord.chord_x_m - chord.centre_x_m) < 1e-9:
        facing = math.pi / 2
    angles = facing + np.linspace(-half, half, 60)
    points = np.column_stack([chord.centre_x_m + chord.radius_m * np.cos(angles), chord.radius_m * np.sin(angles),
                              np.zeros(60)])
    uv, _ = camera.project(points)
    return uv


def _template_error_px(H_n: np.ndarray, truth: Camera, ground_w: np.ndarray) -> np.ndarray:
    """(K,) median pixel distance between where each homography and the true camera draw ground points."""
    hypotheses = cameras_from_homographies(H_n, (W, H), PITCH)
    H_px = pixel_homographies(hypotheses, (W, H))
    drawn = np.einsum("kij,nj->kni", H_px, np.column_stack([ground_w[:, :2], np.ones(len(ground_w))]))
    drawn = drawn[..., :2] / drawn[..., 2:]
    uv, in_front = truth.project(ground_w)
    seen = in_front & truth.in_image(uv)
    return np.median(np.linalg.norm(drawn - uv[None], axis=2)[:, seen], axis=1)


def test_a_penalty_arc_and_its_16_5_m_line_give_the_true_camera():
    truth = _behind_the_goal()
    right_arc = CHORDS[1]
    arc = _arc_px(truth, right_arc, 100.0)
    line = _image_line(truth, (right_arc.chord_x_m, -20.16), (right_arc.chord_x_m, 20.16))
    H_n = arc_line_homographies([arc], [line], (W, H), CHORDS, FOCAL_RANGE_N)
    assert len(H_n)
    ground = np.array([[x, y, 0.0] for x in np.arange(16.0, 52.6, 2.0) for y in np.arange(-30.0, 30.1, 2.0)])
    errors = _template_error_px(H_n, truth, ground)
    assert errors.min() < 1.0  # the whole box, not only the arc and the line, drawn where the truth draws it


def test_a_free_ellipse_of_the_same_short_arc_is_a_third_short_here_the_camera_model_is_not():
    # The arc spans a seventh of its circle in the image: the grid and its narrowing recover f within a few per cent.
    truth = _behind_the_goal()
    chord = CHORDS[1]
    arc = _arc_px(truth, chord, 100.0)
    line = _image_line(truth, (chord.chord_x_m, -20.16), (chord.chord_x_m, 20.16))
    hypotheses = cameras_from_homographies(arc_line_homographies([arc], [line], (W, H), CHORDS, FOCAL_RANGE_N),
                                           (W, H), PITCH)
    focal_px = hypotheses.focal_n * W / 2
    assert np.min(np.abs(focal_px / truth.focal_px - 1.0)) < 0.03


def test_the_centre_circle_and_the_halfway_line_either_way_round():
    truth = Camera.from_degrees(2600.0, 0.0, 3.0, 76.0, -0.4, (4.0, 60.0, -18.0), W, H)
    centre = CHORDS[0]
    arc = _arc_px(truth, centre, 120.0)
    line = _image_line(truth, (0.0, -9.0), (0.0, 9.0))
    H_n = arc_line_homographies([arc], [line], (W, H), CHORDS, FOCAL_RANGE_N)
    ground = np.array([[x, y, 0.0] for x in np.arange(-30.0, 30.1, 2.0) for y in np.arange(-34.0, 34.1, 2.0)])
    errors = _template_error_px(H_n, truth, ground)
    assert errors.min() < 1.0


def test_an_arc_straddling_its_line_is_no_penalty_arc():
    # A penalty arc lies beyond its 16.5 m line: a line through the arc's middle pairs with it as no penalty arc.
    truth = _behind_the_goal()
    chord = CHORDS[1]
    arc = _arc_px(truth, chord, 100.0)
    through = _image_line(truth, (chord.centre_x_m - chord.radius_m + 0.5, -20.0),
                          (chord.centre_x_m - chord.radius_m + 0.5, 20.0))
    H_n = arc_line_homographies([arc], [through], (W, H), CHORDS[1:], FOCAL_RANGE_N)
    ground = np.array([[x, y, 0.0] for x in (36.0, 47.0) for y in (-9.0, 9.0)])
    assert not len(H_n) or _template_error_px(H_n, truth, ground).min() > 20.0


def test_no_arcs_or_no_lines_give_no_hypotheses():
    truth = _behind_the_goal()
    line = _image_line(truth, (36.0, -20.16), (36.0, 20.16))
    assert arc_line_homographies([], [line], (W, H), CHORDS, FOCAL_RANGE_N).shape == (0, 3, 3)
    assert arc_line_homographies([_arc_px(truth, CHORDS[1], 100.0)], [], (W, H), CHORDS, FOCAL_RANGE_N).shape == (
        0, 3, 3)


def _ellipse_through(points_px: np.ndarray) -> ImageEllipse:
    (cx, cy), (d1, d2), angle = cv2.fitEllipse(points_px.astype(np.float32))
    theta = math.radians(angle) + (0.0 if d1 >= d2 else math.pi / 2)
    return ImageEllipse(np.array([cx, cy]), (max(d1, d2) / 2, min(d1, d2) / 2), theta, 500.0)


def test_arc_points_leave_out_a_long_lines_stretch_not_the_arcs_own_straight_pieces():
    truth = _behind_the_goal()
    chord = CHORDS[1]
    arc = _arc_px(truth, chord, 100.0)
    ellipse = _ellipse_through(arc)
    long_line = _image_line(truth, (chord.chord_x_m, -20.16), (chord.chord_x_m, 20.16))
    piece = _image_line(truth, tuple(np.array([chord.centre_x_m - chord.radius_m, -1.0])),
                        tuple(np.array([chord.centre_x_m - chord.radius_m, 1.0])))  # the arc's middle, read straight
    near_line = long_line.centre_px + 1.0 * long_line.normal + np.outer(np.linspace(-50, 50, 20), long_line.direction)
    points = np.vstack([arc, near_line])
    config = CourtArcConfig()
    found = arc_points([ellipse, ellipse], points, [long_line, piece], W, config)
    assert len(found) == 1  # the same arc twice is one arc
    kept = found[0]
    assert len(kept) == min(config.max_arc_points, len(arc))
    assert not np.any(np.abs(kept @ long_line.normal + long_line.offset_px) < 2.0)


@pytest.mark.parametrize("count", [0, 5])
def test_too_few_arc_points_are_no_arc(count):
    truth = _behind_the_goal()
    arc = _arc_px(truth, CHORDS[1], 100.0)
    assert arc_points([_ellipse_through(arc)], arc[:count], [], W) == []
