"""Arc-and-corner hypotheses: a circle's arc and one line of each direction, none of them across it."""

from __future__ import annotations

import math

import numpy as np
from reinit_helpers import image_lines

from broadtrack_graph.detect.marking_structures import ImageLine
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit import court_arc_corners
from broadtrack_graph.reinit.court_arc_corners import arc_corner_homographies, circle_corners
from broadtrack_graph.reinit.court_arcs import arc_line_homographies, pieces_of
from broadtrack_graph.reinit.court_circle import pitch_circle_chords
from broadtrack_graph.reinit.court_lines import cameras_from_homographies, pixel_homographies

PITCH = PitchTemplate()
W, H = 1920, 1080
CIRCLES = pitch_circle_chords(PITCH)  # centre circle, right penalty arc, left penalty arc
CORNERS = circle_corners(PITCH, CIRCLES, 5.0)
FOCAL_RANGE_N = (0.9, 32.0)
BAND_PX = 4.0


def _low_beside_the_box() -> Camera:
    """A camera 7 m up beside the right 16.5 m line, looking across the pitch at the right penalty arc, the far
    touchline and the halfway line; the 16.5 m line is out of view."""
    return Camera.from_degrees(3487.0, 0.0, -16.9, 83.4, 0.1, (35.9, 41.8, -7.2), W, H)


def _image_line(camera: Camera, a_w, b_w) -> ImageLine:
    """The straight marking from a_w to b_w (pitch metres) as the map's line finder returns it, end to end."""
    return image_lines(camera, [((*a_w, 0.0), (*b_w, 0.0))], extent_share=1.0)[0]


def _penalty_arc_px(camera: Camera, degrees: float = 57.0) -> np.ndarray:
    """The right penalty arc's image points (its painted part faces the halfway line), frame pixels."""
    angles = math.pi + np.radians(np.linspace(-degrees / 2, degrees / 2, 50))
    uv, _ = camera.project(np.column_stack([41.5 + 9.15 * np.cos(angles), 9.15 * np.sin(angles), np.zeros(50)]))
    return uv


def _template_error_px(H_n: np.ndarray, truth: Camera) -> np.ndarray:
    """(K,) median pixel distance between where each homography and the true camera draw the right half's ground."""
    grid = np.array([[x, y, 0.0] for x in np.linspace(0.0, 52.0, 27) for y in np.linspace(-34.0, 34.0, 35)])
    hypotheses = cameras_from_homographies(H_n, (W, H), PITCH)
    drawn = np.einsum("kij,nj->kni", pixel_homographies(hypotheses, (W, H)), np.column_stack([grid[:, :2],
                                                                                                np.ones(len(grid))]))
    drawn = drawn[..., :2] / drawn[..., 2:]
    uv, in_front = truth.project(grid)
    seen = in_front & truth.in_image(uv)
    return np.median(np.linalg.norm(drawn - uv[None], axis=2)[:, seen], axis=1)


def test_the_corners_name_each_circles_lines_with_their_side_rules():
    right = [c for c in CORNERS if c.centre_x_m > 0]
    by_lines = {(c.x_m, c.y_m): c for c in right}
    box = by_lines[(36.0, -34.0)]  # the 16.5 m line: the painted arc lies beyond it
    assert box.x_rule == 1 and box.y_rule == -1
    assert box.shares == (5.5 / 9.15, 34.0 / 9.15)
    halfway = by_lines[(0.0, 34.0)]  # the halfway line, 4.5 radii off: the arc on the centre's side
    assert halfway.x_rule == -1 and math.isclose(halfway.shares[0], 41.5 / 9.15)
    assert by_lines[(0.0, 34.0)].handedness == -by_lines[(0.0, -34.0)].handedness
    centre = [c for c in CORNERS if c.centre_x_m == 0.0]
    assert centre and all(c.x_rule == 0 and c.y_rule == 0 for c in centre)
    assert (0.0, 34.0) in {(c.x_m, c.y_m) for c in centre}  # the halfway line through it, a touchline
    # the goal area's side lines end 47 m from the centre circle: never its lines
    assert all(abs(c.y_m) != 9.16 for c in centre)


def test_an_arc_with_a_touchline_and_the_halfway_line_beside_it_gives_the_true_camera():
    truth = _low_beside_the_box()
    arc = _penalty_arc_px(truth)
    lines = [_image_line(truth, (-10.0, -34.0), (30.0, -34.0)), _image_line(truth, (0.0, -30.0), (0.0, -10.0))]
    H_n = arc_corner_homographies([arc], lines, (W, H), CORNERS, FOCAL_RANGE_N, BAND_PX)
    errors = _template_error_px(H_n, truth)
    assert errors.min() < 1.0
    # its twin half a turn about the centre spot explains the image as well; nothing else comes near
    assert np.sum(errors < 50.0) == 1
    # the chord's tier asks for the 16.5 m line across the arc, which is out of view: nothing near the truth
    chords = arc_line_homographies([arc], lines, (W, H), CIRCLES, FOCAL_RANGE_N)
    assert not len(chords) or _template_error_px(chords, truth).min() > 50.0


def test_clutter_lines_beyond_the_longest_are_not_paired():
    truth = _low_beside_the_box()
    arc = _penalty_arc_px(truth)
    lines = [_image_line(truth, (-10.0, -34.0), (30.0, -34.0)), _image_line(truth, (0.0, -30.0), (0.0, -10.0))]
    rng = np.random.default_rng(0)
    clutter = []
    for _ in range(20):  # short strokes anywhere in the image
        a = rng.uniform((0, 0), (W, H))
        b = a + rng.normal(0.0, 30.0, 2)
        direction = (b - a) / np.linalg.norm(b - a)
        normal = np.array([-direction[1], direction[0]])
        half = np.linalg.norm(b - a) / 2
        clutter.append(ImageLine(normal, -float(normal @ (a + b) / 2), (a + b) / 2, direction, (-half, half),
                                 2 * half))
    H_n = arc_corner_homographies([arc], clutter + lines, (W, H), CORNERS, FOCAL_RANGE_N, BAND_PX)
    assert _template_error_px(H_n, truth).min() < 1.0


def test_the_arcs_own_straight_pieces_are_told_from_lines():
    truth = _low_beside_the_box()
    arc = _penalty_arc_px(truth)
    angles = math.pi + np.radians([-8.0, 8.0])
    piece = _image_line(truth, (41.5 + 9.15 * math.cos(angles[0]), 9.15 * math.sin(angles[0])),
                        (41.5 + 9.15 * math.cos(angles[1]), 9.15 * math.sin(angles[1])))
    touchline = _image_line(truth, (-10.0, -34.0), (30.0, -34.0))
    assert pieces_of(arc, [piece, touchline], BAND_PX).tolist() == [True, False]


def test_nothing_without_an_arc_or_two_lines():
    truth = _low_beside_the_box()
    line = _image_line(truth, (-10.0, -34.0), (30.0, -34.0))
    assert arc_corner_homographies([], [line, line], (W, H), CORNERS, FOCAL_RANGE_N, BAND_PX).shape == (0, 3, 3)
    assert arc_corner_homographies([_penalty_arc_px(truth)], [line], (W, H), CORNERS, FOCAL_RANGE_N,
                                   BAND_PX).shape == (0, 3, 3)


def test_the_grid_asks_the_kinds_only_where_the_arc_and_the_lines_angle_leave_room():
    truth = _low_beside_the_box()
    arc_n = (_penalty_arc_px(truth) - (W / 2, H / 2)) / (W / 2)
    lines = [_image_line(truth, (-10.0, -34.0), (30.0, -34.0)), _image_line(truth, (0.0, -30.0), (0.0, -10.0)),
             _image_line(truth, (36.0, -34.0), (36.0, -20.0))]
    pairs = [(a, b) for a in range(3) for b in range(3) if a != b]
    ends_n = (np.array([[lines[a].ends_px(), lines[b].ends_px()] for a, b in pairs]) - (W / 2, H / 2)) / (W / 2)
    kinds = np.array(sorted({corner.kind() for corner in CORNERS}), float)
    grid = np.stack(np.meshgrid(np.geomspace(*FOCAL_RANGE_N, 14), np.radians(np.linspace(30.0, 89.5, 20)), [0.0],
                                indexing="ij"), axis=-1).reshape(-1, 3)
    every = court_arc_corners._errors(grid, arc_n, ends_n, kinds, 20.0)
    within = court_arc_corners._errors(grid, arc_n, ends_n, kinds, 20.0, within=0.3)
    kept = np.isfinite(within)
    assert kept.any() and (~kept & np.isfinite(every)).any()  # the bound leaves some out, and keeps some
    assert np.array_equal(within[kept], every[kept])  # what it keeps, to the bit
    assert (every[~kept] > 0.3).all()  # what it leaves out errs over the bound anyway
