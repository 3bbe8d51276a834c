"""Fitting a camera to per-class line points (Levenberg-Marquardt on point-to-curve distances)."""

from __future__ import annotations

import numpy as np
import pytest
from reinit_helpers import labelled_lines as _lines
from reinit_helpers import reference_camera as _camera

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.state import project_state
from broadtrack_graph.geometry.template import TemplateCurves, closest_on_polyline
from broadtrack_graph.reinit.linefit import LineFitConfig, _Problem, fit_camera_to_lines

W, H = 960, 540
PITCH = PitchTemplate()
CURVES = TemplateCurves(PITCH)


def test_fit_camera_to_lines_converges_from_a_perturbed_start():
    truth = _camera(k1=0.04)
    lines = _lines(truth, np.random.default_rng(1), noise_px=0.3)
    start = truth.replace(pan_rad=truth.pan_rad + 0.02, tilt_rad=truth.tilt_rad - 0.01, focal_px=truth.focal_px * 1.08,
                          k1=0.0)
    result = fit_camera_to_lines(start, lines, CURVES, LineFitConfig())
    assert 0.0 < result.max_distance_px < 1.5
    assert result.camera.focal_px == pytest.approx(truth.focal_px, rel=0.03)
    assert result.camera.pan_deg == pytest.approx(truth.pan_deg, abs=0.2)


def _association_class_by_class(problem, state):
    """What :meth:`_Problem.associate` gives (the geometry, the distances, the points missed), class by class with
    :func:`closest_on_polyline` (the reference)."""
    uv, _, front = project_state(state, problem.all_samples, W, H, want_jacobian=False)
    anchors, normals, targets, dists, missing = [], [], [], {}, 0
    offsets = np.cumsum([0] + [len(CURVES.samples_w[name]) for name in problem.names])
    for j, name in enumerate(problem.names):
        poly, ok = uv[offsets[j]:offsets[j + 1]], front[offsets[j]:offsets[j + 1]]
        points, valid = problem.points[name], ok[:-1] & ok[1:]
        if not valid.any():
            dists[name], missing = np.full(len(points), np.nan), missing + len(points)
            continue
        seg, t, d = closest_on_polyline(points, poly, valid)
        samples = CURVES.samples_w[name]
        anchors.append(samples[seg] + t[:, None] * (samples[seg + 1] - samples[seg]))
        direction = poly[seg + 1] - poly[seg]
        direction /= np.maximum(np.linalg.norm(direction, axis=1, keepdims=True), 1e-12)
        normals.append(np.stack([-direction[:, 1], direction[:, 0]], axis=1))
        targets.append(points)
        dists[name] = d
    return np.vstack(anchors), np.vstack(normals), np.vstack(targets), dists, missing


def test_association_of_all_classes_at_once_is_the_nearest_segment_of_each_class_to_the_bit():
    camera = _camera()
    lines = _lines(camera, np.random.default_rng(3), noise_px=4.0)
    lines["Circle central"] = np.vstack([lines["Circle central"], [[900.0, 30.0], [5.0, 500.0]]])  # far from it
    problem = _Problem(lines, CURVES, W, H, LineFitConfig(), None)
    inside_the_pitch = camera.to_vector()
    inside_the_pitch[5:8] = (0.0, 0.0, -13.0)  # the classes on the camera's side of the halfway line are behind it
    missing = []
    for state in (camera.to_vector(), camera.replace(pan_rad=camera.pan_rad + 0.05, focal_px=900.0).to_vector(),
                  inside_the_pitch):
        association = problem.associate(state)
        got, want = (*association.geometry(), association.dists, association.missing), \
            _association_class_by_class(problem, state)
        for a, b in zip(got[:3], want[:3]):
            np.testing.assert_array_equal(a, b)
        assert got[3].keys() == want[3].keys()
        for name in want[3]:
            np.testing.assert_array_equal(got[3][name], want[3][name])
        assert got[4] == want[4]
        missing.append(got[4])
    assert missing[0] == 0 and missing[2] > 0


def test_association_within_reach_is_the_nearest_segment_of_each_class_to_the_bit_and_measures_no_other_pair():
    camera = _camera()
    problem = _Problem(_lines(camera, np.random.default_rng(4), noise_px=2.0), CURVES, W, H, LineFitConfig(), None)
    for state, every_pair_made in ((camera.replace(pan_rad=camera.pan_rad + 0.002).to_vector(), False),
                                   (camera.replace(pan_rad=camera.pan_rad + 0.05).to_vector(), True)):  # 40 px off
        association = problem.associate(state)
        got, want = association.geometry(), _association_class_by_class(problem, state)
        for a, b in zip(got, want[:3]):
            np.testing.assert_array_equal(a, b)
        for name in want[3]:
            np.testing.assert_array_equal(association.dists[name], want[3][name])
        assert (problem._pairs is not None) == every_pair_made
