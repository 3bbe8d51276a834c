"""Fitting a camera to per-class line points (Levenberg-Marquardt on point-to-curve distances)."""

from __future__ import annotations

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves
from broadtrack_graph.reinit.linefit import LineFitConfig, fit_camera_to_lines

W, H = 960, 540
PITCH = PitchTemplate()
CURVES = TemplateCurves(PITCH)


def _camera(pan=-12.0, tilt=76.0, focal=1100.0, k1=0.0, position=(1.5, 57.0, -13.0), roll=0.3):
    return Camera.from_degrees(focal, k1, pan, tilt, roll, position, W, H)


def _lines(camera, rng=None, noise_px=0.0, per_class=12):
    """Visible template classes as labelled points (like an annotation)."""
    out = {}
    for name, pts in PITCH.sample_uniform(0.5).items():
        uv, front = camera.project(pts)
        ok = front & camera.in_image(uv)
        if ok.sum() < 4:
            continue
        sel = uv[ok][np.linspace(0, ok.sum() - 1, per_class).astype(int)]
        if rng is not None:
            sel = sel + rng.normal(0, noise_px, sel.shape)
        out[name] = sel
    return out


def test_fit_camera_to_lines_converges_from_a_perturbed_start():
    truth = _camera(k1=0.04)
    lines = _lines(truth, np.random.default_rng(1), noise_px=0.3)
    start = truth.replace(pan_rad=truth.pan_rad + 0.02, tilt_rad=truth.tilt_rad - 0.01, focal_px=truth.focal_px * 1.08,
                          k1=0.0)
    result = fit_camera_to_lines(start, lines, CURVES, LineFitConfig())
    assert 0.0 < result.max_distance_px < 1.5
    assert result.camera.focal_px == pytest.approx(truth.focal_px, rel=0.03)
    assert result.camera.pan_deg == pytest.approx(truth.pan_deg, abs=0.2)
