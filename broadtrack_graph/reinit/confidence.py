"""Confidence of a camera: agreement of the detected marking map with the projected template.

Compared only where markings can be detected: template samples inside the image, on
the field (not under players when a player mask is given) and wide enough in the
image to be found (a 12 cm line at least ``min_line_width_px`` working pixels wide).
Both sets live at one reference width (960 px) with a tolerance at that width, so
the measure does not change with the frame resolution:

* recall R: share of the detectable template within ``tolerance_px`` of a detected
  marking pixel (divided by at least ``min_template_px`` samples, so a camera that
  shows almost no template cannot score high);
* precision P: share of detected marking pixels within ``tolerance_px`` of the template.

confidence = F-beta(P, R) with beta = 2 (recall weighted: grass texture and clutter
leave specks that no camera explains). Below ``threshold`` (0.5, BroadTrack) the
tracker re-initialises and ignores flow from the previous camera. No I/O.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from scipy.spatial import cKDTree

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.template import TemplateCurves, project_template

DEFAULT_THRESHOLD = 0.5


@dataclass(frozen=True)
class ConfidenceConfig:
    """Settings of :func:`camera_confidence` (pixels at ``work_width_px``)."""

    work_width_px: int = 960  # comparison width (the weight-free detector's working width)
    tolerance_px: float = 2.5  # a template sample / marking pixel this close to the other set agrees
    template_spacing_px: float = 1.0  # densified template sampling
    min_line_width_px: float = 0.7  # template parts thinner than this in the image are not detectable
    min_template_px: int = 150  # recall denominator floor (samples, about pixels of template)
    beta: float = 2.0  # F-beta weight of recall over precision
    threshold: float = DEFAULT_THRESHOLD  # below: re-initialise


def _resized(mask: np.ndarray, w: int, h: int) -> np.ndarray:
    if mask.shape == (h, w):
        return mask.astype(bool)
    return cv2.resize(mask.astype(np.uint8), (w, h), interpolation=cv2.INTER_NEAREST) > 0


def confidence_parts(camera: Camera, marking_mask: np.ndarray, curves: TemplateCurves | None = None,
                     config: ConfidenceConfig = ConfidenceConfig(), field_mask: np.ndarray | None = None,
                     player_mask: np.ndarray | None = None) -> dict:
    """Precision, recall, their F-beta and the sample counts (see module docstring)."""
    curves = curves or TemplateCurves()
    H, W = marking_mask.shape
    w = config.work_width_px
    h = max(1, int(round(H * w / W)))
    if marking_mask.shape == (h, w):
        marks = marking_mask.astype(bool)
    else:
        # Thin maps must not vanish when reduced: any marking pixel in a cell marks the cell.
        marks = cv2.resize(marking_mask.astype(np.uint8) * 255, (w, h),
                           interpolation=cv2.INTER_AREA if W > w else cv2.INTER_NEAREST) > 0
    found = cv2.findNonZero(marks.astype(np.uint8))
    marks_uv = np.zeros((0, 2)) if found is None else found.reshape(-1, 2).astype(float)
    template = project_template(camera, curves, w, h, config.template_spacing_px)
    uv = template.uv_px[template.width_m_px * (w / camera.width_px) >= config.min_line_width_px]
    if len(uv) and (field_mask is not None or player_mask is not None):
        col = np.clip(np.round(uv[:, 0]).astype(int), 0, w - 1)
        row = np.clip(np.round(uv[:, 1]).astype(int), 0, h - 1)
        keep = np.ones(len(uv), bool)
        if field_mask is not None:
            keep &= _resized(field_mask, w, h)[row, col]
        if player_mask is not None:
            keep &= ~_resized(player_mask, w, h)[row, col]
        uv = uv[keep]
    if field_mask is not None and len(marks_uv):
        marks_uv = marks_uv[_resized(field_mask, w, h)[marks_uv[:, 1].astype(int), marks_uv[:, 0].astype(int)]]
    tol = config.tolerance_px
    recall = precision = 0.0
    if len(uv) and len(marks_uv):
        d_template, _ = cKDTree(marks_uv).query(uv, distance_upper_bound=tol)
        recall = float(np.sum(np.isfinite(d_template)) / max(len(uv), config.min_template_px))
        d_marks, _ = cKDTree(uv).query(marks_uv, distance_upper_bound=tol)
        precision = float(np.mean(np.isfinite(d_marks)))
    b2 = config.beta**2
    score = (1 + b2) * precision * recall / (b2 * precision + recall) if precision + recall > 0 else 0.0
    return {"confidence": float(score), "precision": precision, "recall": recall,
            "template_samples": int(len(uv)), "marking_pixels": int(len(marks_uv))}


def camera_confidence(camera: Camera, marking_mask: np.ndarray, curves: TemplateCurves | None = None,
                      config: ConfidenceConfig = ConfidenceConfig(), field_mask: np.ndarray | None = None,
                      player_mask: np.ndarray | None = None) -> float:
    """Agreement in [0, 1] of the detected marking map and the camera's projected template.

    Args:
        camera: the camera to check (any resolution).
        marking_mask: (H, W) bool map of detected markings (frame size or a reduced size of the same aspect).
        field_mask, player_mask: optional bool maps (any size of the same aspect); the template only
            counts where the field is visible and no player hides it.

    Returns:
        F-beta of precision and recall (module docstring); 0 when either set is empty.
    """
    return confidence_parts(camera, marking_mask, curves, config, field_mask, player_mask)["confidence"]


def needs_reinit(confidence: float, threshold: float = DEFAULT_THRESHOLD) -> bool:
    """True when the camera is not trusted: re-initialise and drop flow from the previous camera."""
    return confidence < threshold
