"""Test helpers shared by the re-initialisation tests: a reference camera, labelled lines, image lines of pitch
segments, template error, a view of a penalty area and its lines."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.benchmarks import template_error
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate

W, H = 960, 540
PITCH = PitchTemplate()
GROUND_SAMPLES_W = np.vstack([p for n, p in PITCH.sample_uniform(1.0).items() if PITCH.is_on_ground(n)])


def reference_camera(pan=-12.0, tilt=76.0, focal=1100.0, k1=0.0, position=(1.5, 57.0, -13.0), roll=0.3):
    """A main camera at 960x540 (degrees, pixels, metres)."""
    return Camera.from_degrees(focal, k1, pan, tilt, roll, position, W, H)


def labelled_lines(camera, rng=None, noise_px=0.0, per_class=12):
    """Visible template classes as labelled points (like an annotation): class -> (per_class, 2) pixels."""
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


def median_template_error_px(camera, truth):
    """Median pixel distance between the ground template (1 m samples) seen by truth and by camera (the benches'
    :func:`~broadtrack_graph.benchmarks.template_error.median_template_error_px`)."""
    return template_error.median_template_error_px(camera, truth, GROUND_SAMPLES_W)


def image_lines(camera, segments_w, extent_share: float = 0.8):
    """The exact image lines (no distortion) of pitch segments ((2, 3) metres each), as the Hough step returns them
    (over ``extent_share`` of each segment's image, about its middle)."""
    from broadtrack_graph.detect.marking_structures import ImageLine

    out = []
    for a, b in segments_w:
        (ua, ub), front = camera.project(np.array([a, b], float))
        assert front.all()
        direction = (ub - ua) / np.linalg.norm(ub - ua)
        normal = np.array([-direction[1], direction[0]])
        centre = 0.5 * (ua + ub)
        half = 0.5 * np.linalg.norm(ub - ua)
        extent = extent_share * half
        out.append(ImageLine(normal, float(-normal @ centre), centre, direction, (-extent, extent), 2 * extent))
    return out


def box_view() -> Camera:
    """A camera behind and beside the right goal, seeing the penalty area (both line directions)."""
    return Camera.from_degrees(1100.0, 0.0, -46.0, 63.0, 0.4, (75.0, 30.0, -22.0), 1280, 720)


BOX_SEGMENTS = [  # pieces of the right penalty area's lines that box_view sees
    ((52.5, -15.0, 0.0), (52.5, 15.0, 0.0)),  # goal line (x = 52.5)
    ((36.0, -15.0, 0.0), (36.0, 15.0, 0.0)),  # 16.5 m line (x = 36)
    ((47.0, -9.16, 0.0), (47.0, 9.16, 0.0)),  # goal area line (x = 47)
    ((36.5, 20.16, 0.0), (52.0, 20.16, 0.0)),  # penalty area side (y = 20.16)
    ((36.5, -20.16, 0.0), (52.0, -20.16, 0.0)),  # the other side (y = -20.16)
    ((47.5, 9.16, 0.0), (52.0, 9.16, 0.0)),  # goal area side (y = 9.16)
]
