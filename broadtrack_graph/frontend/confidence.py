"""Confidence of a camera: Jaccard index between the detected marking map and the projected template.

Both maps are compared at a reduced width with a tolerance of a few pixels (the
template is drawn thick, the marking map dilated), inside the image. Below
``threshold`` (0.5 by default, BroadTrack) the tracker re-initialises and ignores
flow from the previous camera. No I/O.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from broadtrack_graph.camera import Camera
from broadtrack_graph.frontend.linefit import TemplateCurves
from broadtrack_graph.frontend.weightfree import template_mask

DEFAULT_THRESHOLD = 0.5


@dataclass(frozen=True)
class ConfidenceConfig:
    """Settings of :func:`camera_confidence`."""

    work_width_px: int = 480  # comparison width
    line_thickness_px: int = 7  # template line thickness at that width (tolerance of a few pixels)
    dilate_px: int = 7  # marking map dilation at that width
    threshold: float = DEFAULT_THRESHOLD  # below: re-initialise


def camera_confidence(camera: Camera, marking_mask: np.ndarray, curves: TemplateCurves | None = None,
                      config: ConfidenceConfig = ConfidenceConfig(), field_mask: np.ndarray | None = None) -> float:
    """Jaccard index |A and B| / |A or B| of the marking map A and the projected template B.

    Args:
        camera: the camera to check (any resolution).
        marking_mask: (H, W) bool map of detected markings at the frame's resolution.
        field_mask: optional (H, W) bool; the template is only counted where the field is visible
            (markings hidden behind players or outside the grass cannot be detected).

    Returns:
        Jaccard index in [0, 1]; 0 when both maps are empty.
    """
    curves = curves or TemplateCurves()
    H, W = marking_mask.shape
    w = min(config.work_width_px, W)
    h = max(1, int(round(H * w / W)))
    marks = cv2.resize(marking_mask.astype(np.uint8) * 255, (w, h), interpolation=cv2.INTER_AREA) > 0
    if config.dilate_px > 1:
        marks = cv2.dilate(marks.astype(np.uint8), np.ones((config.dilate_px, config.dilate_px), np.uint8)) > 0
    ground = [n for n in curves.samples_w if curves.pitch.is_on_ground(n)]
    template = template_mask(camera, curves, w, h, config.line_thickness_px, classes=ground)
    if field_mask is not None:
        template &= cv2.resize(field_mask.astype(np.uint8), (w, h), interpolation=cv2.INTER_NEAREST) > 0
    union = np.count_nonzero(marks | template)
    return float(np.count_nonzero(marks & template) / union) if union else 0.0


def needs_reinit(confidence: float, threshold: float = DEFAULT_THRESHOLD) -> bool:
    """True when the camera is not trusted: re-initialise and drop flow from the previous camera."""
    return confidence < threshold
