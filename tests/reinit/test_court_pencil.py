"""Court-model hypotheses from three lines of one direction and one across them (a zoomed goal mouth)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from reinit_helpers import image_lines

from broadtrack_graph.detect.marking_structures import ImageLine
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.court_pencil import pencil_hypotheses

PITCH = PitchTemplate()
W, H = 1280, 720

GOAL_MOUTH = [  # the goal line, the goal area's front, the 16.5 m line, and one goal area side
    ((52.5, -9.0, 0.0), (52.5, 9.0, 0.0)),
    ((47.0, -9.16, 0.0), (47.0, 9.16, 0.0)),
    ((36.0, -15.0, 0.0), (36.0, 15.0, 0.0)),
    ((47.5, 9.16, 0.0), (52.0, 9.16, 0.0)),
]


@pytest.mark.parametrize("focal_px, pan_deg, tilt_deg, roll_deg, position_m", [
    (1100.0, -46.0, 63.0, 0.8, (75.0, 30.0, -22.0)),  # behind and beside the goal, a wide lens
    (4800.0, -60.0, 80.0, -1.5, (85.0, 45.0, -20.0)),  # a long lens from a corner, rolled
])
def test_three_lines_and_one_across_give_the_true_camera(focal_px, pan_deg, tilt_deg, roll_deg, position_m):
    truth = Camera.from_degrees(focal_px, 0.0, pan_deg, tilt_deg, roll_deg, position_m, W, H)
    hypotheses = pencil_hypotheses(image_lines(truth, GOAL_MOUTH), (W, H), PITCH)
    gap = np.linalg.norm(hypotheses.C_w - truth.position_m, axis=1)
    k = int(np.argmin(gap))
    assert gap[k] < 1e-6
    assert hypotheses.focal_n[k] * W / 2 == pytest.approx(focal_px, rel=1e-9)
    assert np.allclose(hypotheses.angles_rad[k], np.radians([pan_deg, tilt_deg, roll_deg]), atol=1e-9)


def test_two_lines_of_a_direction_make_no_hypothesis():
    truth = Camera.from_degrees(1100.0, 0.0, -46.0, 63.0, 0.8, (75.0, 30.0, -22.0), W, H)
    lines = image_lines(truth, GOAL_MOUTH[:2] + GOAL_MOUTH[3:])
    assert len(pencil_hypotheses(lines, (W, H), PITCH)) == 0


def test_the_line_across_is_found_among_stronger_arc_pieces():
    # A penalty arc's flat pieces, found as short lines with more support than a goal area's short side: the side is
    # still tried as the line across.
    truth = Camera.from_degrees(4800.0, 0.0, -60.0, 80.0, -1.5, (85.0, 45.0, -20.0), W, H)
    lines = image_lines(truth, GOAL_MOUTH)
    bends = np.radians(np.linspace(-50.0, 50.0, 6))  # the right penalty arc, outside the area, in five pieces
    ends = [(41.5 - 9.15 * np.cos(t), 9.15 * np.sin(t), 0.0) for t in bends]
    arc = list(zip(ends[:-1], ends[1:]))
    strong = 10.0 * lines[3].support_px  # each piece a stronger line than the side
    pieces = [replace(piece, support_px=strong, extent_px=(-0.6 * strong, 0.6 * strong))
              for piece in image_lines(truth, arc)]
    hypotheses = pencil_hypotheses(lines + pieces, (W, H), PITCH)
    assert np.linalg.norm(hypotheses.C_w - truth.position_m, axis=1).min() < 1e-6


def _segment(a, b, support_px: float):
    """The image line through pixels a and b, drawn on its middle 60 % (its ends clear of where it meets others)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    direction = (b - a) / np.linalg.norm(b - a)
    normal = np.array([-direction[1], direction[0]])
    centre, half = 0.5 * (a + b), 0.5 * np.linalg.norm(b - a)
    return ImageLine(normal, float(-normal @ centre), centre, direction, (-0.6 * half, 0.6 * half), support_px)


def test_the_family_of_three_is_found_among_stronger_pairs_of_lines():
    # Three long strong lines that meet two by two (a triangle of board edges, say) give meeting points that
    # outvote the goal mouth's three lines: only a point met by three lines or more can be the family's.
    truth = Camera.from_degrees(1100.0, 0.0, -46.0, 63.0, 0.8, (75.0, 30.0, -22.0), W, H)
    lines = image_lines(truth, GOAL_MOUTH)
    strong = 10.0 * max(line.support_px for line in lines)
    corners = [(60.0, 40.0), (1200.0, 60.0), (640.0, 700.0)]
    triangle = [_segment(corners[k], corners[(k + 1) % 3], strong) for k in range(3)]
    hypotheses = pencil_hypotheses(lines + triangle, (W, H), PITCH)
    assert len(hypotheses) and np.linalg.norm(hypotheses.C_w - truth.position_m, axis=1).min() < 1e-6
