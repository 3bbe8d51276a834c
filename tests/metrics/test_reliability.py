"""Right or wrong against a true camera, and the reliability table of written cameras."""

from __future__ import annotations

import math

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.template import TemplateSampling
from broadtrack_graph.metrics.reliability import (
    line_disagreement_px,
    merged_summaries,
    reliability_summary,
    reliability_table,
)

SAMPLING = TemplateSampling()


def _camera(**change) -> Camera:
    camera = Camera.from_degrees(1900.0, 0.0, 0.0, 74.0, 0.0, (0.0, 55.0, -12.0), 1920, 1080)
    return camera.replace(**change) if change else camera


def test_the_true_camera_disagrees_by_nothing_at_any_resolution():
    truth = _camera()
    assert line_disagreement_px(truth, truth, SAMPLING) == pytest.approx(0.0, abs=1e-6)
    assert line_disagreement_px(truth.rescaled(960, 540), truth, SAMPLING) == pytest.approx(0.0, abs=1e-6)


def test_a_tilt_moves_the_markings_by_the_focal_length_times_the_angle():
    truth = _camera()
    turned = truth.replace(tilt_rad=truth.tilt_rad + math.radians(0.1))
    expected = 1900.0 / 2 * math.radians(0.1)  # at 960 x 540, half the focal length; a near-horizontal line moves
    error = line_disagreement_px(turned, truth, SAMPLING)
    assert 0.7 * expected < error < 1.6 * expected


def test_a_line_sliding_along_itself_is_not_an_error():
    """A camera panned a little moves the near touchline (horizontal in the image) along itself only."""
    truth = _camera()
    panned = truth.replace(pan_rad=truth.pan_rad + math.radians(0.05))
    moved = truth.project(np.array([[0.0, 34.0, 0.0]]))[0] - panned.project(np.array([[0.0, 34.0, 0.0]]))[0]
    assert abs(moved[0, 0]) > 1.0  # the point moved along the line by more than a pixel at 1920
    assert line_disagreement_px(panned, truth, SAMPLING) < 2.0


def test_the_twin_camera_half_a_turn_about_the_centre_is_wrong():
    truth = _camera()
    twin = truth.replace(pan_rad=truth.pan_rad + math.pi, position_m=-np.asarray(truth.position_m) * [1, 1, -1])
    assert line_disagreement_px(twin, truth, SAMPLING) > 100.0


def test_a_view_of_the_sky_judges_nothing():
    truth = _camera(tilt_rad=math.radians(150.0))
    assert line_disagreement_px(truth, truth, SAMPLING) is None


def test_the_table_bins_by_confidence_and_counts_the_right_ones():
    rows = reliability_table([0.05, 0.35, 0.39, 0.95, 1.0, float("nan")], [False, True, False, True, True, True])
    by_bin = {(r.low, r.high): (r.cameras, r.right) for r in rows}
    assert by_bin[(0.0, 0.3)] == (1, 0)
    assert by_bin[(0.3, 0.4)] == (2, 1)
    assert by_bin[(0.9, 1.0)] == (2, 2)  # the last bin holds a confidence of exactly 1
    assert sum(r.cameras for r in rows) == 5  # NaN is left out
    with pytest.raises(ValueError, match="2 confidences for 1 verdicts"):
        reliability_table([0.1, 0.2], [True])


def test_summaries_add_up():
    first = reliability_summary([0.95, 0.65], [True, False])
    second = reliability_summary([0.92], [True])
    assert first["written_right_share"] == 0.5
    merged = merged_summaries([first, None, second])
    assert merged["cameras"] == 3 and merged["written_right_share"] == pytest.approx(2 / 3, abs=1e-4)
    top = merged["rows"][-1]
    assert top["cameras"] == 2 and top["right_share"] == 1.0


def test_a_marking_laid_outside_the_image_counts_by_how_far_it_reaches_in():
    truth = _camera()
    shown = line_disagreement_px(truth.replace(pan_rad=truth.pan_rad + math.pi / 2), truth, SAMPLING)
    assert shown > 200.0  # looking along the touchline instead: every marking shown is laid elsewhere
