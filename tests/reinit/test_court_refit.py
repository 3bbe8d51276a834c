"""Homographies refitted on every straight marking they explain, on lines projected from a known camera."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.aim import aim_angles
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.court_lines import pitch_line_offsets
from broadtrack_graph.reinit.court_refit import pitch_lines, refit_on_lines

W, H = 1280, 720
PITCH = PitchTemplate()
POSITION = np.array([20.0, 60.0, -22.0])
TRUTH = Camera(2030.0, 0.0, *aim_angles(POSITION, np.array([42.0, 0.0, 0.0])), 0.0, POSITION, W, H)  # the right box


def _normalised_homography(camera: Camera) -> np.ndarray:
    K_n = np.diag([2 * camera.focal_px / W, 2 * camera.focal_px / W, 1.0])
    R, t = camera.R_cw, -camera.R_cw @ camera.position_m
    return K_n @ np.column_stack([R[:, 0], R[:, 1], t])


def _image_line_ends(camera: Camera) -> np.ndarray:
    """(L, 2, 2) the visible ends of every straight ground marking in view, normalised coordinates."""
    ends = []
    for name, points in PITCH.sample_uniform(0.25).items():
        element = PITCH.elements[name]
        if not PITCH.is_on_ground(name) or not hasattr(element, "start_w"):
            continue
        uv, front = camera.project(points)
        seen = front & camera.in_image(uv)
        if seen.sum() >= 40:
            shown = uv[seen]
            ends.append([shown[0], shown[-1]])
    return (np.array(ends) - [W / 2, H / 2]) / (W / 2)


def _pixels(H_n: np.ndarray, points_w: np.ndarray) -> np.ndarray:
    uvw = np.column_stack([points_w[:, :2], np.ones(len(points_w))]) @ H_n.T
    return uvw[:, :2] / uvw[:, 2:] * (W / 2)


def test_a_hypothesis_a_few_pixels_off_is_pulled_onto_the_lines_it_explains():
    ends = _image_line_ends(TRUTH)
    assert len(ends) >= 5
    lines_w = pitch_lines(*pitch_line_offsets(PITCH))
    off = TRUTH.replace(pan_rad=TRUTH.pan_rad + 0.002, tilt_rad=TRUTH.tilt_rad - 0.002,
                        position_m=np.asarray(TRUTH.position_m) + [1.5, -1.0, 0.5])
    ground = np.vstack([p for name, p in PITCH.sample_uniform(1.0).items() if PITCH.is_on_ground(name)])
    uv, front = TRUTH.project(ground)
    ground = ground[front & TRUTH.in_image(uv)]
    truth_px = _pixels(_normalised_homography(TRUTH), ground)
    before = np.median(np.linalg.norm(_pixels(_normalised_homography(off), ground) - truth_px, axis=1))
    assert before > 5.0  # the hypothesis is visibly off
    refitted, done = refit_on_lines(_normalised_homography(off)[None], ends, lines_w, gate_n=0.04)
    assert done[0]
    after = np.median(np.linalg.norm(_pixels(refitted[0], ground) - truth_px, axis=1))
    assert after < 0.5


def test_a_hypothesis_explaining_too_few_lines_or_singular_is_left_as_it_was():
    ends = _image_line_ends(TRUTH)
    lines_w = pitch_lines(*pitch_line_offsets(PITCH))
    far_off = TRUTH.replace(pan_rad=TRUTH.pan_rad + 0.2)  # its lines nowhere near the image's
    given = np.stack([_normalised_homography(far_off), np.zeros((3, 3))])
    refitted, done = refit_on_lines(given, ends, lines_w, gate_n=0.04)
    assert not done.any()
    assert np.array_equal(refitted[0], given[0])
    _, done = refit_on_lines(_normalised_homography(TRUTH)[None], ends[:3], lines_w, gate_n=0.04)
    assert not done.any()  # three image lines: under min_lines
