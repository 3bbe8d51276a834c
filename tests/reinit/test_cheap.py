"""Cheap re-initialisation (broadtrack_graph.reinit.cheap): guesses refined on the marking map of a rendered frame."""

from __future__ import annotations

import math

import numpy as np
from reinit_helpers import median_template_error_px

from broadtrack_graph.detect.weightfree import WeightFreeDetector
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves
from broadtrack_graph.reinit.cheap import refine_guesses
from broadtrack_graph.synth.clip import render_clip

PITCH = PitchTemplate()
CURVES = TemplateCurves(PITCH)


def test_a_nearby_guess_is_refined_onto_the_markings_and_the_best_guess_wins():
    frame = render_clip("main", 1, 960, 540, seed=2).frames[0]
    truth = frame.camera
    det = WeightFreeDetector(PITCH).detect(frame.image)
    near = truth.replace(pan_rad=truth.pan_rad + math.radians(0.6), tilt_rad=truth.tilt_rad - math.radians(0.3),
                         focal_px=truth.focal_px * 1.03)
    far = truth.replace(pan_rad=truth.pan_rad + math.radians(25.0))
    assert median_template_error_px(near, truth) > 5.0
    result = refine_guesses([("far", far), ("near", near)], det, CURVES)
    assert result.hypothesis == "refined near"
    assert result.score.jaccard > 0.6
    assert median_template_error_px(result.camera, truth) < 1.5
    # Guesses at another resolution are rescaled to the frame's.
    rescaled = refine_guesses([("near", near.rescaled(1920, 1080))], det, CURVES)
    assert (rescaled.camera.width_px, rescaled.camera.height_px) == (960, 540)
    assert refine_guesses([], det, CURVES).camera is None
    assert refine_guesses([("near", near)], None, CURVES).camera is None


def test_a_guess_held_on_its_tripod_is_refined_there():
    frame = render_clip("main", 1, 960, 540, seed=2).frames[0]
    truth = frame.camera
    det = WeightFreeDetector(PITCH).detect(frame.image)
    near = truth.replace(pan_rad=truth.pan_rad + math.radians(0.6), focal_px=truth.focal_px * 1.03)
    held = refine_guesses([("near", near)], det, CURVES, hold_position=True)
    np.testing.assert_array_equal(held.camera.position_m, truth.position_m)
    assert median_template_error_px(held.camera, truth) < 1.5


def test_a_guess_refined_onto_the_pitch_is_dropped_like_any_implausible_camera():
    from types import SimpleNamespace

    from broadtrack_graph.geometry.camera import Camera
    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.geometry.template import TemplateCurves
    from broadtrack_graph.reinit.cheap import refine_guesses

    curves = TemplateCurves(PitchTemplate())
    on_pitch = Camera.from_degrees(1200.0, 0.0, 0.0, 70.0, 0.0, (0.0, 10.0, -12.0), 960, 540)  # over the grass
    mask = np.zeros((540, 960), bool)
    mask[300, 100:900] = True
    detections = SimpleNamespace(marking_mask=mask, marking_points_px=np.column_stack(
        [np.arange(100, 900, 20), np.full(40, 300)]).astype(float), width_px=960, height_px=540,
        field_mask=None, player_mask=None)
    result = refine_guesses([("over the pitch", on_pitch)], detections, curves)
    assert result.camera is None and "on the pitch" in result.reason
