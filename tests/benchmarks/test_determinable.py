"""``bench placements --random``: which frames' markings determine a camera (two lines of each direction, or a
circle and a line)."""

from __future__ import annotations

import math

import numpy as np

from broadtrack_graph.benchmarks.determinable import MIN_LINE_PX, determinability
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.synth.field_cameras import aim_angles


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
