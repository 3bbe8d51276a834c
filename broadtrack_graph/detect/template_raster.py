"""The projected pitch template drawn as a (H, W) mask (the pictures and the detector's template mask).

The numpy projection (:func:`broadtrack_graph.geometry.template.project_template`) lives in
geometry; this module only draws the usable runs of each class's projected samples with OpenCV.
No I/O.
"""

from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import LINE_CLASSES
from broadtrack_graph.geometry.template import TemplateCurves, finite_runs, usable_samples


def template_mask(camera: Camera, curves: TemplateCurves, width_px: int, height_px: int, thickness_px: int = 1,
                  classes=LINE_CLASSES) -> np.ndarray:
    """(H, W) bool: the projected template drawn as lines of the given thickness."""
    canvas = np.zeros((height_px, width_px), dtype=np.uint8)
    cam = camera.rescaled(width_px, height_px)
    for name in classes:
        uv, front = cam.project(curves.samples_w[name])
        for a, b in finite_runs(usable_samples(uv, front, width_px, height_px)):
            cv2.polylines(canvas, [np.round(uv[a:b]).astype(np.int32)], False, 255, max(1, int(thickness_px)))
    return canvas > 0
