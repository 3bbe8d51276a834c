"""Which frames' markings determine a camera (two lines of each direction, or a circle and a line), and whether the
markings a camera explains on a map fix it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from broadtrack_graph.geometry.aim import aim_angles
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.determinable import (
    MIN_LINE_PX,
    TRIPOD_CAMERA_UNKNOWNS,
    Determinability,
    determinability,
    fixes_camera,
)
from broadtrack_graph.geometry.pitch import PitchTemplate


def camera(position, aim, hfov_deg, width_px=1280, height_px=720, k1=0.0) -> Camera:
    pan, tilt = aim_angles(np.array(position, float), np.array(aim, float))
    return Camera(width_px / 2 / math.tan(math.radians(hfov_deg) / 2), k1, pan, tilt, 0.0, np.array(position, float),
                  width_px, height_px)


def test_a_wide_main_camera_view_counts():
    seen = determinability(camera((0.0, 68.0, -22.0), (0.0, 0.0, 0.0), 50.0))
    assert seen.determinable
    assert seen.x_lines >= 2 and seen.y_lines >= 2
    assert seen.visible_px["Side line top"] > 1000 and seen.curve_shares["Circle central"] == 1.0


def test_a_close_view_of_grass_with_one_line_does_not_count():
    seen = determinability(camera((0.0, 70.0, -20.0), (0.0, 22.0, 0.0), 8.0))
    assert not seen.determinable
    assert (seen.x_lines, seen.y_lines, seen.curves) == (0, 1, ())
    assert seen.visible_px["Middle line"] > MIN_LINE_PX
    assert sum(v > 0 for v in seen.visible_px.values()) == 1


def test_a_circle_and_a_line_count():
    seen = determinability(camera((0.0, 68.0, -22.0), (0.0, 0.0, 0.0), 22.0))
    assert seen.x_lines < 2 and seen.y_lines < 2, "not counted by the lines alone"
    assert seen.curves == ("Circle central",) and seen.determinable


def test_collinear_markings_count_as_one_line():
    # The whole pitch from high up: six classes along x show over 60 px, on four distinct lines (the two
    # penalty areas' long sides on each side lie on one line y = +-20.16).
    seen = determinability(camera((0.0, 110.0, -60.0), (0.0, 0.0, 0.0), 70.0))
    names = ("Big rect. left bottom", "Big rect. right bottom", "Big rect. left top", "Big rect. right top",
             "Side line bottom", "Side line top")
    along_x = [n for n in names if seen.visible_px[n] >= MIN_LINE_PX]
    assert len(along_x) == 6 and seen.x_lines == 4
    assert seen.y_lines == 7 and seen.determinable


def test_markings_behind_the_camera_or_off_the_image_do_not_count():
    # Looking away from the pitch (at the ground behind the main stand): nothing of the pitch is in view.
    seen = determinability(camera((0.0, 68.0, -22.0), (0.0, 120.0, 0.0), 50.0))
    assert not seen.determinable and sum(seen.visible_px.values()) == 0
    assert all(share == 0 for share in seen.curve_shares.values())


def test_the_rule_reads_pixels_at_the_frame_size():
    # The same view at a quarter of the size: lines a quarter as long; the circle keeps its share.
    full = determinability(camera((0.0, 68.0, -22.0), (0.0, 0.0, 0.0), 22.0))
    small = determinability(camera((0.0, 68.0, -22.0), (0.0, 0.0, 0.0), 22.0, 320, 180))
    assert np.isclose(small.visible_px["Middle line"], full.visible_px["Middle line"] / 4, rtol=0.02)
    assert small.curve_shares == full.curve_shares


def _marking_map(cam: Camera, names) -> np.ndarray:
    """A detected marking map at the camera's size showing only the named markings (their projected samples)."""
    import cv2

    marks = np.zeros((cam.height_px, cam.width_px), np.uint8)
    for name, points in PitchTemplate().sample_uniform(0.05, list(names)).items():
        uv, front = cam.project(points)
        uv = uv[front & cam.in_image(uv)]
        cells = np.clip(np.round(uv).astype(int), 0, [cam.width_px - 1, cam.height_px - 1])
        marks[cells[:, 1], cells[:, 0]] = 1
    return cv2.dilate(marks, np.ones((2, 2), np.uint8)) > 0


def test_only_the_markings_on_the_map_count_when_a_map_is_given():
    wide = camera((0.0, 68.0, -22.0), (0.0, 0.0, 0.0), 50.0)
    everything = determinability(wide, explained_by=_marking_map(wide, PitchTemplate().elements))
    alone = determinability(wide)
    assert (everything.x_lines, everything.y_lines) == (alone.x_lines, alone.y_lines)
    assert fixes_camera(everything)
    one_line = determinability(wide, explained_by=_marking_map(wide, ["Side line top"]))
    assert (one_line.x_lines, one_line.y_lines) == (1, 0) and not one_line.determinable
    assert not fixes_camera(one_line)


@pytest.mark.parametrize("x_lines, y_lines, shares, fixed", [
    (2, 2, {}, True),  # two of each direction: a homography
    (2, 1, {}, False),  # one unknown left
    (3, 1, {}, True),  # three and one: seven constraints with the principal point known
    (4, 0, {}, False),  # one direction only: the camera slides along it
    (2, 1, {"Circle central": 0.27}, True),  # an arc adds its place, size and bend
    (1, 0, {"Circle central": 0.27}, False),
    (1, 0, {"Circle central": 0.5}, True),  # a circle and a line
    (0, 0, {"Circle central": 1.0}, False),  # a whole circle alone: its roll about the centre is free
])
def test_a_camera_is_fixed_by_as_many_constraints_as_it_has_unknowns(x_lines, y_lines, shares, fixed):
    seen = Determinability(False, x_lines, y_lines, (), curve_shares=shares)
    assert fixes_camera(seen) is fixed


@pytest.mark.parametrize("x_lines, y_lines, shares, surplus, fixed", [
    (1, 0, {"Circle central": 0.5}, 0, True),  # a circle and a line fix it exactly ...
    (1, 0, {"Circle central": 0.5}, 1, False),  # ... with nothing over
    (2, 2, {}, 1, True),  # a homography's 8 constraints: one over
    (3, 1, {}, 1, True),
    (2, 1, {"Circle central": 0.27}, 2, True),  # 6 + 3
    (2, 1, {"Circle central": 0.27}, 3, False),
    (4, 0, {}, 0, False),  # the surplus does not make parallel lines cross
])
def test_a_surplus_asks_for_that_many_constraints_over_the_unknowns(x_lines, y_lines, shares, surplus, fixed):
    seen = Determinability(False, x_lines, y_lines, (), curve_shares=shares)
    assert fixes_camera(seen, surplus) is fixed


@pytest.mark.parametrize("x_lines, y_lines, shares, fixed", [
    (1, 0, {"Circle central": 0.27}, True),  # an arc and a touchline: 5 constraints, f and three angles unknown
    (0, 0, {"Circle central": 1.0}, True),  # a whole circle: its roll about the centre is the tripod's
    (2, 1, {}, True),
    (1, 1, {}, False),  # one line of each direction fixes it exactly, with nothing over
    (3, 0, {}, False),  # parallel lines alone stay refused
])
def test_a_camera_on_a_known_tripod_has_four_unknowns(x_lines, y_lines, shares, fixed):
    seen = Determinability(False, x_lines, y_lines, (), curve_shares=shares)
    assert fixes_camera(seen, 1, unknowns=TRIPOD_CAMERA_UNKNOWNS) is fixed
    assert not fixes_camera(seen, 1)  # from nothing, none of these


@pytest.mark.parametrize("x_lines, y_lines, curves, grid", [
    (2, 2, (), True),  # a homography from the lines alone
    (3, 5, ("Circle central",), True),
    (1, 5, ("Circle right",), False),  # one line across: the lines of the other direction slide along it
    (2, 1, ("Circle central",), False),  # fixed with the circle, not by a grid of lines
    (0, 0, (), False),
])
def test_a_grid_of_lines_is_two_straight_markings_of_each_direction(x_lines, y_lines, curves, grid):
    assert Determinability(False, x_lines, y_lines, curves).line_grid is grid
