"""The painted width of a marking in the image: its strip's two edges projected, across the line's image."""

from __future__ import annotations

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.paint_width import MARKING_WIDTH_M, painted_widths_px
from broadtrack_graph.geometry.pitch import LINE_CLASSES, PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves, project_template

W, H = 960, 540


def _line_distance_px(a, b, point):
    """Distance (pixels) of ``point`` from the image line through a and b."""
    d = (b - a) / np.linalg.norm(b - a)
    return abs(d[0] * (point[1] - a[1]) - d[1] * (point[0] - a[0]))


def test_a_painted_line_is_as_wide_as_the_image_of_its_two_edges_and_foreshortened_across_the_view():
    # A camera 6 m up behind the left goal, looking down the pitch: the lines across its view (the halfway line, the
    # far goal line) are seen at a grazing angle. Each sample's width is checked against the distance from the image
    # of one edge line of the 12 cm strip to the other edge's point beside the sample (a pinhole camera maps lines to
    # lines).
    camera = Camera.from_degrees(900.0, 0.0, 90.0, 84.0, 0.0, (-62.0, 0.0, -6.0), W, H)
    curves = TemplateCurves(PitchTemplate())
    names = ["Middle line", "Side line right", "Side line top", "Big rect. left main", "Small rect. left main"]
    points, _, joins = curves.stacked(names)
    uv, front = camera.project(points)
    widths = painted_widths_px(camera, points, uv, joins)
    checked = 0
    for k in np.flatnonzero(front & np.isfinite(widths) & np.append(joins, False))[::3]:
        along = points[k + 1] - points[k]
        across = np.array([-along[1], along[0], 0.0]) / np.linalg.norm(along[:2]) * (MARKING_WIDTH_M / 2)
        edge_a, _ = camera.project(np.array([points[k] + across, points[k + 1] + across]))
        edge_b, _ = camera.project(np.array([points[k] - across]))
        assert widths[k] == pytest.approx(_line_distance_px(edge_a[0], edge_a[1], edge_b[0]), rel=0.02, abs=1e-4)
        checked += 1
    assert checked > 50
    # Foreshortened: across the view, a small fraction of the scale f / depth at the same depth.
    template = project_template(camera, curves, W, H, 1.0, paint_widths=True)
    assert template.paint_width_px is not None and len(template.paint_width_px) == len(template.uv_px)
    for name, at_most in (("Middle line", 0.15), ("Side line right", 0.1)):
        shown = template.class_index == LINE_CLASSES.index(name)
        assert shown.sum() > 100
        assert np.median(template.paint_width_px[shown] / template.width_m_px[shown]) < at_most
    assert project_template(camera, curves, W, H, 1.0).paint_width_px is None  # made only when asked
