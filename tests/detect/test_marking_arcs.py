"""Arcs of the marking map (detect/marking_arcs.py): a penalty arc drawn from a known camera, found as its ellipse."""

from __future__ import annotations

import math

import cv2
import numpy as np

from broadtrack_graph.detect.marking_arcs import marking_arcs
from broadtrack_graph.detect.marking_ellipses import marking_ellipses
from broadtrack_graph.detect.marking_structures import MarkingStructureConfig, marking_lines
from broadtrack_graph.detect.template_raster import template_mask
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves

W, H = 960, 540
PITCH = PitchTemplate()
CURVES = TemplateCurves(PITCH, line_step_m=0.5, circle_step_m=0.05)
# The court model's structures: the map cut along its long lines before curves are fitted.
STRUCTURES = MarkingStructureConfig(max_lines=24, candidate_lines=48, ellipse_cut_line_px=160.0)


def _high_behind_the_left_goal() -> Camera:
    """A camera 35 m up, 22 m behind the left goal line, looking along the pitch at the penalty arc."""
    return Camera.from_degrees(1300.0, 0.0, 90.0, 52.0, 0.0, (-74.5, 0.0, -35.0), W, H)


def _true_ellipse(camera: Camera, name: str):
    """(centre (2,), semi-axes (a, b)) of the image of a pitch circle, fitted to the whole projected circle."""
    d = PITCH.dimensions
    centre_x = {"Circle left": -(d.length_m / 2 - d.penalty_mark_distance_m), "Circle central": 0.0}[name]
    angle = np.linspace(0.0, 2.0 * math.pi, 720, endpoint=False)
    circle = np.column_stack([centre_x + d.centre_circle_radius_m * np.cos(angle),
                              d.centre_circle_radius_m * np.sin(angle), np.zeros_like(angle)])
    uv, front = camera.project(circle)
    (cx, cy), (d1, d2), _ = cv2.fitEllipse(uv[front].astype(np.float32))
    return np.array([cx, cy]), (max(d1, d2) / 2, min(d1, d2) / 2)


def test_a_penalty_arc_beside_its_line_is_found_where_the_circle_projects():
    camera = _high_behind_the_left_goal()
    mask = template_mask(camera, CURVES, W, H, classes=("Circle left", "Big rect. left main"))
    lines = marking_lines(mask, W, STRUCTURES)
    assert marking_ellipses(mask, W, STRUCTURES, lines=lines) == []  # a third of its ellipse: no whole ellipse
    arcs = marking_arcs(mask, W, lines, STRUCTURES)
    assert len(arcs) == 1
    centre, (a, b) = _true_ellipse(camera, "Circle left")
    assert np.linalg.norm(arcs[0].centre_px - centre) < 0.04 * a
    assert abs(arcs[0].semi_axes_px[0] - a) < 0.03 * a and abs(arcs[0].semi_axes_px[1] - b) < 0.05 * b


def test_straight_markings_and_specks_make_no_arc():
    camera = _high_behind_the_left_goal()
    straight = template_mask(camera, CURVES, W, H, classes=("Big rect. left main", "Big rect. left top",
                                                            "Big rect. left bottom", "Small rect. left main"))
    assert marking_arcs(straight, W, marking_lines(straight, W, STRUCTURES), STRUCTURES) == []
    specks = np.random.default_rng(3).random((H, W)) < 0.01
    assert marking_arcs(specks, W, marking_lines(specks, W, STRUCTURES), STRUCTURES) == []
