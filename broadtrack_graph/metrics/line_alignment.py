"""Is a camera aligned with the lines visible in its frame? A check independent of the tracker's detector.

The projected ground markings (the template densified to ``spacing_px``) are compared
with the frame's own line-like pixels: bright, thin structures found by a white top-hat
(kernel about a marking's width scaled to the frame) above ``tophat_threshold`` grey
levels, on or next to grass. Of the projected samples that lie on grass (not on players,
boards or graphics: the grass mask, grown by the top-hat kernel so that the marking's own
pixels count), the share within ``tolerance_px`` of a line-like pixel is the alignment
(0..1). A right camera scores high wherever its markings are visible; a camera off by
more than a marking's width scores low. It shares nothing with the weight-free detector
(different filters, no ridge or naming step), so it can judge it.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.template import TemplateCurves, project_template


@dataclass(frozen=True)
class AlignmentConfig:
    """Settings of :func:`line_alignment`."""

    tophat_per_width: float = 1.0 / 110.0  # top-hat kernel (pixels) per image width pixel (at least 5)
    tophat_threshold: float = 12.0  # grey levels above the local background of a line-like pixel
    tolerance_fraction: float = 1.0 / 320.0  # tolerance (pixels) per image width pixel (at least 2)
    spacing_px: float = 4.0  # spacing of the projected samples (pixels)
    min_points: int = 30  # fewer projected samples on grass: the frame is not scored
    aligned_share: float = 0.8  # a frame whose share is at least this is "aligned" (right cameras score 0.9-1.0 at 720p;
    #                             a 0.3 deg tilt error about 0.3, a 0.3 deg pan error along a touchline about 0.75)


def line_pixels(image_bgr: np.ndarray, config: AlignmentConfig = AlignmentConfig()) -> tuple[np.ndarray, np.ndarray]:
    """(line-like mask, grass region mask), both (H, W) bool, of one (H, W, 3) uint8 BGR frame."""
    H, W = image_bgr.shape[:2]
    k = max(5, int(round(W * config.tophat_per_width)) | 1)
    grey = cv2.cvtColor(image_bgr, cv2.COLOR_BGR2GRAY)
    tophat = cv2.morphologyEx(grey, cv2.MORPH_TOPHAT, cv2.getStructuringElement(cv2.MORPH_RECT, (k, k)))
    hsv = cv2.cvtColor(image_bgr, cv2.COLOR_BGR2HSV)
    grass = cv2.inRange(hsv, (30, 40, 30), (95, 255, 255))
    region = cv2.dilate(grass, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (k, k))) > 0
    # Markings are surrounded by grass: the region is grass grown by a marking's width, then
    # shrunk back where it is not grass on both sides (closing fills the markings, not players).
    region &= cv2.morphologyEx(grass, cv2.MORPH_CLOSE, cv2.getStructuringElement(cv2.MORPH_RECT, (k, k))) > 0
    return (tophat > config.tophat_threshold) & region, region


def line_alignment(image_bgr: np.ndarray, camera: Camera, curves: TemplateCurves,
                   config: AlignmentConfig = AlignmentConfig()) -> tuple[float | None, int]:
    """(share of projected marking samples on line-like pixels, samples scored) for one frame.

    Args:
        image_bgr: (H, W, 3) uint8 BGR frame.
        camera: the frame's camera (any resolution; rescaled to the frame).
        curves: the template's 3D samples.

    Returns:
        (share in 0..1, or None when fewer than ``min_points`` samples fall on grass; the count).
    """
    H, W = image_bgr.shape[:2]
    lines, region = line_pixels(image_bgr, config)
    projected = project_template(camera, curves, W, H, spacing_px=config.spacing_px)
    uv = np.round(projected.uv_px).astype(int) if len(projected.uv_px) else np.zeros((0, 2), int)
    if not len(uv):
        return None, 0
    x, y = np.clip(uv[:, 0], 0, W - 1), np.clip(uv[:, 1], 0, H - 1)
    on_grass = region[y, x]
    if on_grass.sum() < config.min_points:
        return None, int(on_grass.sum())
    r = max(2, int(round(W * config.tolerance_fraction)))
    near = cv2.dilate(lines.astype(np.uint8), cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))) > 0
    hits = near[y[on_grass], x[on_grass]]
    return float(hits.mean()), int(on_grass.sum())
