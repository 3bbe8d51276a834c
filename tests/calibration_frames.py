"""Synthetic annotated frames for the calibration tests: three cameras and their labelled line points."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.io.annotations import annotation_from_pixels

W, H = 960, 540
PITCH = PitchTemplate()


def annotation(camera: Camera, rng, noise_px=0.7):
    lines = {}
    for name, pts in PITCH.sample_uniform(0.5).items():
        uv, front = camera.project(pts)
        ok = front & camera.in_image(uv)
        if ok.sum() >= 4:
            sel = uv[ok][np.linspace(0, ok.sum() - 1, 8).astype(int)]
            lines[name] = sel + rng.normal(0, noise_px, sel.shape)
    return annotation_from_pixels(lines, W, H)


def cameras():
    return [
        Camera.from_degrees(1000.0, -0.02, -20.0, 75.0, 0.4, (-1.0, 58.0, -14.0), W, H),
        Camera.from_degrees(2200.0, 0.0, 33.0, 77.0, -0.2, (2.0, 62.0, -16.0), W, H),
        # labels seen from the far side (mirrored convention): focal point at -y
        Camera.from_degrees(1300.0, 0.0, 170.0, 76.0, 0.0, (0.0, -56.0, -13.0), W, H),
    ]
