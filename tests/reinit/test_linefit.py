"""Fitting a camera to per-class line points (Levenberg-Marquardt on point-to-curve distances)."""

from __future__ import annotations

import numpy as np
import pytest
from reinit_helpers import labelled_lines as _lines
from reinit_helpers import reference_camera as _camera

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves
from broadtrack_graph.reinit.linefit import LineFitConfig, fit_camera_to_lines

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
