"""Line-pair hypotheses: cameras putting two straight markings on two pitch lines."""

from __future__ import annotations

import numpy as np
from reinit_helpers import median_template_error_px as _median_template_error_px

from broadtrack_graph.detect.marking_structures import ImageLine
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.line_pairs import line_pair_cameras, pitch_lines

PITCH = PitchTemplate()


def test_line_pair_cameras_contain_a_tight_roll_free_camera():
    truth = Camera.from_degrees(2.25 * 1920, 0.0, 10.6, 79.6, 0.0, (0.0, 55.0, -12.0), 1920, 1080)
    lines = []
    for name in ("Middle line", "Side line top"):
        uv, front = truth.project(PITCH.sample_uniform(0.5)[name])
        uv = uv[front & truth.in_image(uv)]
        centre = uv.mean(axis=0)
        direction = np.linalg.svd(uv - centre)[2][0]
        normal = np.array([-direction[1], direction[0]])
        along = (uv - centre) @ direction
        lines.append(ImageLine(normal, float(-normal @ centre), centre, direction,
                               (float(along.min()), float(along.max())), float(np.ptp(along))))
    pairs = line_pair_cameras(lines, (0.0, 55.0, -12.0), (1920, 1080), PITCH)
    assert 0 < len(pairs.focals_px) < 500
    errors = [_median_template_error_px(Camera(f, 0.0, p, t, 0.0, np.array([0.0, 55.0, -12.0]), 1920, 1080), truth)
              for p, t, f in zip(pairs.pans_rad, pairs.tilts_rad, pairs.focals_px)]
    # f is gridded (4 % steps): the closest camera is within a grid step of the truth, not exactly on it.
    assert 0.0 < min(errors) < 15.0


def test_pitch_lines_are_the_painted_straight_lines():
    points_w, directions_w, extents = pitch_lines(PITCH)
    assert points_w.shape == directions_w.shape == (len(extents), 3)
    np.testing.assert_allclose(np.linalg.norm(directions_w, axis=1), 1.0)
    # The middle line: x = 0 along y, painted from touchline to touchline.
    middle = [k for k in range(len(extents)) if directions_w[k, 1] == 1.0 and points_w[k, 0] == 0.0]
    assert len(middle) == 1
    half_width = PITCH.dimensions.width_m / 2
    assert extents[middle[0]] == [(-half_width, half_width)]
