"""Re-initialisation from labelled line points: homography decomposition, global search + fit."""

from __future__ import annotations

import numpy as np
import pytest
from reinit_helpers import labelled_lines as _lines
from reinit_helpers import reference_camera as _camera

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves, TemplateSampling
from broadtrack_graph.reinit.lines import camera_from_homography, homography_from_lines, reinit_from_lines
from broadtrack_graph.reinit.scoring import score_labelled

W, H = 960, 540
PITCH = PitchTemplate()
CURVES = TemplateCurves(PITCH)
SAMPLING = TemplateSampling(PITCH)


def test_homography_decomposition_recovers_the_camera():
    truth = _camera(k1=0.0)
    lines = _lines(truth)
    Hmat = homography_from_lines(lines, PITCH)
    assert Hmat is not None
    camera = camera_from_homography(Hmat, W, H)
    assert camera.focal_px == pytest.approx(truth.focal_px, rel=0.01)
    np.testing.assert_allclose(camera.position_m, truth.position_m, atol=0.3)
    assert camera.pan_deg == pytest.approx(truth.pan_deg, abs=0.1)
    assert homography_from_lines({k: v for k, v in list(lines.items())[:2]}, PITCH) is None


@pytest.mark.parametrize("case", [
    dict(pan=-12.0, tilt=76.0, focal=1100.0, position=(1.5, 57.0, -13.0)),  # wide, many lines
    dict(pan=28.0, tilt=74.0, focal=1900.0, position=(-2.0, 60.0, -15.0)),  # right penalty area
])
def test_reinit_from_lines_reaches_every_class(case):
    truth = _camera(**case)
    lines = _lines(truth, np.random.default_rng(2), noise_px=0.5)
    result = reinit_from_lines(lines, W, H, PITCH, curves=CURVES, sampling=SAMPLING)
    assert result.camera is not None
    score = score_labelled(result.camera, lines, 5.0, SAMPLING)
    assert score.fn == 0 and score.inlier_share == 1.0
    np.testing.assert_allclose(result.camera.position_m, truth.position_m, atol=3.0)


def test_reinit_from_lines_without_usable_class_is_none():
    result = reinit_from_lines({"Line unknown": np.zeros((3, 2))}, W, H, PITCH, curves=CURVES, sampling=SAMPLING)
    assert result.camera is None and result.reason
