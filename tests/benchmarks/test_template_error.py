"""The benches' template error of a camera against the truth (broadtrack_graph.benchmarks.template_error)."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.benchmarks.template_error import median_template_error_px, template_errors_px
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.synth.motion import generate_camera_track

W, H = 960, 540


def test_template_errors_zero_for_the_truth_and_grow_with_a_pan_error():
    pitch = PitchTemplate()
    camera = generate_camera_track("main", 1, W, H, seed=0).cameras[0]
    points_w = np.vstack(list(pitch.sample_uniform(1.0).values()))
    assert np.max(template_errors_px(camera, camera, points_w)) < 1e-9
    state = camera.to_vector()
    state[2] += np.radians(0.1)
    moved = type(camera).from_vector(state, W, H)
    errors = template_errors_px(moved, camera, points_w)
    # 0.1 deg of pan moves the image by about f * 0.1 deg.
    expected = camera.focal_px * np.radians(0.1)
    assert 0.7 * expected < np.median(errors) < 1.3 * expected


def test_the_median_is_none_without_an_estimate_or_points_in_view_and_inf_counts_points_behind():
    camera = generate_camera_track("main", 1, W, H, seed=0).cameras[0]
    points_w = np.vstack(list(PitchTemplate().sample_uniform(1.0).values()))
    assert median_template_error_px(None, camera, points_w) is None
    behind_the_camera = camera.position_m + 10.0 * camera.R_cw[2] * -1.0  # 10 m behind, along the optical axis
    assert median_template_error_px(camera, camera, behind_the_camera[None]) is None
    turned = camera.replace(pan_rad=camera.pan_rad + np.pi)  # looks away: every point the truth sees is behind it
    assert median_template_error_px(turned, camera, points_w) == np.inf
