"""The hypotheses of a family of image lines and one line across it (the frame court_pencil and court_level share)."""

from __future__ import annotations

import numpy as np
from reinit_helpers import box_view, image_lines

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.court_across import family_and_across_hypotheses
from broadtrack_graph.reinit.court_lines import pitch_line_offsets

PITCH = PitchTemplate()
W, H = 1280, 720
GOAL_MOUTH = [  # three lines along y (x = 52.5, 47, 36) and, across them, the goal area's side (y = 9.16)
    ((52.5, -9.0, 0.0), (52.5, 9.0, 0.0)),
    ((47.0, -9.16, 0.0), (47.0, 9.16, 0.0)),
    ((36.0, -15.0, 0.0), (36.0, 15.0, 0.0)),
    ((47.5, 9.16, 0.0), (52.0, 9.16, 0.0)),
]


def _asked(lines, min_lines, max_family_lines=4):
    """The calls made of ``homographies_of``: (family lines, lines across, family offsets, across offsets, family is
    along x), none of which gives a homography."""
    calls = []

    def homographies_of(family_n, across_n, family_m, across_m, family_is_x):
        calls.append((family_n, across_n, family_m, across_m, family_is_x))
        return np.zeros((0, 3, 3))

    hypotheses = family_and_across_hypotheses(lines, (W, H), PITCH, min_lines, 2, max_family_lines, 8, homographies_of)
    assert len(hypotheses) == 0
    return calls


def test_every_choice_of_the_familys_lines_is_asked_with_the_line_across_as_either_direction():
    lines = image_lines(box_view(), GOAL_MOUTH)
    along_x, along_y = pitch_line_offsets(PITCH)
    calls = _asked(lines, 2)
    # the three lines along y, two at a time (3 choices), each as either direction, with the goal area's side across
    family_calls = [c for c in calls if len(c[1]) == 1]
    assert len(family_calls) == 6
    for family_n, across_n, family_m, across_m, family_is_x in family_calls:
        assert family_n.shape == (2, 3) and across_n.shape == (1, 3)
        assert np.array_equal(family_m, along_x if family_is_x else along_y)
        assert np.array_equal(across_m, along_y if family_is_x else along_x)
    assert len(_asked(lines, 3)) == 2  # three at a time: one choice, either direction


def test_a_family_without_enough_lines_or_a_line_across_is_not_asked():
    lines = image_lines(box_view(), GOAL_MOUTH)
    assert _asked(lines[:3], 2) == []  # three lines of one direction, none across
    assert _asked(lines[:2] + lines[3:], 3) == []  # two lines of a direction: no family of three
