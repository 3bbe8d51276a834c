"""The weight-free detector finds the same markings at 640x360 and 1920x1080 (pixel settings live at its
working width, not the input size), and caps the named points per class."""

from __future__ import annotations

import numpy as np
import pytest

from broadtrack_graph.detect.detector import PredictedCamera
from broadtrack_graph.detect.point_cells import capped_cell_means
from broadtrack_graph.detect.weightfree import WeightFreeDetector
from broadtrack_graph.detect.weightfree_config import WeightFreeConfig
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves, distances_to_polyline
from broadtrack_graph.synth.clip import render_clip

PITCH = PitchTemplate()
FINE = TemplateCurves(PITCH, line_step_m=0.1, circle_step_m=0.05)


def _detect(width: int, height: int):
    frame = render_clip("main", 1, width, height, seed=4).frames[0]
    det = WeightFreeDetector(PITCH).detect(frame.image, PredictedCamera(frame.camera, 2.0 * width / 960))
    return det, frame.camera


@pytest.fixture(scope="module")
def small_and_large():
    return _detect(640, 360), _detect(1920, 1080)


def _class_errors(det, truth) -> dict[str, float]:
    """Median distance (as a share of the frame width) of each named class's points to its true projection."""
    out = {}
    for name, points in det.lines_px.items():
        uv, front = truth.project(FINE.samples_w[name])
        out[name] = float(np.median(distances_to_polyline(points, uv[front]))) / det.width_px
    return out


def test_the_same_markings_are_named_at_360p_and_1080p(small_and_large):
    (small, truth_s), (large, truth_l) = small_and_large
    errors_s, errors_l = _class_errors(small, truth_s), _class_errors(large, truth_l)
    assert len(errors_l) >= 4, errors_l
    common = set(errors_s) & set(errors_l)
    # The same classes (at most one missing either way) ...
    assert len(set(errors_s) ^ set(errors_l)) <= 1 and len(common) >= 4, (sorted(errors_s), sorted(errors_l))
    # ... on their markings within about 1 px at 960 (a share of the width, so the same at any size).
    for name in common:
        assert errors_s[name] < 1.2 / 960 and errors_l[name] < 1.2 / 960, (name, errors_s[name], errors_l[name])
    # The marking maps and points live at the working width: similar amounts at both sizes.
    ratio = small.marking_mask.sum() / large.marking_mask.sum()
    assert 0.7 < ratio < 1.4, ratio
    points = len(small.marking_points_px) / len(large.marking_points_px)
    assert 0.7 < points < 1.4, points


def test_named_points_are_capped_per_class(small_and_large):
    (_, _), (large, _) = small_and_large
    cap = WeightFreeConfig().max_points_per_class
    assert max(len(p) for p in large.lines_px.values()) <= cap


def test_capped_cell_means_averages_on_coarser_cells():
    t = np.linspace(0.0, 600.0, 6001)
    line = np.column_stack([t, 0.5 * t + 3.0])
    plain = capped_cell_means(line, 3.0, 0)
    assert len(plain) > 180  # uncapped: about one point per 3 px cell along the line
    capped = capped_cell_means(line, 3.0, 100)
    assert 50 <= len(capped) <= 100
    # Still on the line and spread along all of it.
    np.testing.assert_allclose(capped[:, 1], 0.5 * capped[:, 0] + 3.0, atol=1e-6)
    assert capped[:, 0].min() < 15 and capped[:, 0].max() > 585
    few = line[:40]
    np.testing.assert_allclose(capped_cell_means(few, 3.0, 100), capped_cell_means(few, 3.0, 0))
