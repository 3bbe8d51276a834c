"""Is a camera aligned with the lines visible in its frame? A check independent of the tracker's detector.

The projected ground markings (the template densified to ``spacing_px``) are compared
with the frame's own line-like pixels: bright, thin structures found by a white top-hat
(kernel about a marking's width scaled to the frame) above ``tophat_threshold`` grey
levels, on or next to grass. Only projected samples on grass count (not on players,
boards or graphics: the grass mask, grown by the top-hat kernel so that the marking's own
pixels count). Two shares are given:

- ``all_markings``: of those samples, the share within ``tolerance_px`` of a line-like
  pixel. A marking the frame does not show (a far touchline merged into the shadow of the
  boards, a faint line at 360p) counts as a miss, so right cameras of low-resolution
  frames score 0.7.
- ``visible_markings``: the same share over the samples near a visible marking only (a
  line-like pixel within ``visible_factor`` tolerances), provided such samples are at least
  ``min_visible_share`` of the samples on grass. A camera off by more than the tolerance
  puts its markings next to the visible ones (misses) or on bare grass (not counted, and
  too few counted samples fail the frame). This is the figure that judges a frame.

A right camera scores high wherever its markings are visible; a camera off by more than a
marking's width scores low. It shares nothing with the weight-free detector (different
filters, no ridge or naming step), so it can judge it.
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
    visible_factor: float = 3.0  # a sample is next to a visible marking within this many tolerances ...
    min_visible_share: float = 0.5  # ... and such samples must be at least this share of the samples on grass


@dataclass(frozen=True)
class Alignment:
    """How one camera sits on one frame's line-like pixels (module docstring).

    all_markings: share (0..1) of the projected samples on grass within the tolerance of a line-like pixel.
    visible_markings: the same share over the samples next to a visible marking; 0 when those are fewer
        than ``min_visible_share`` of the samples on grass.
    samples: projected samples on grass; visible_samples: those next to a visible marking.
    """

    all_markings: float
    visible_markings: float
    samples: int
    visible_samples: int

    def aligned(self, config: AlignmentConfig) -> bool:
        """The frame counts as aligned: ``visible_markings`` at least ``config.aligned_share``."""
        return self.visible_markings >= config.aligned_share


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
                   config: AlignmentConfig = AlignmentConfig(),
                   pixels: tuple[np.ndarray, np.ndarray] | None = None) -> Alignment | None:
    """How the camera's projected ground markings sit on the frame's line-like pixels (module docstring).

    Args:
        image_bgr: (H, W, 3) uint8 BGR frame.
        camera: the frame's camera (any resolution; rescaled to the frame).
        curves: the template's 3D samples.
        pixels: the frame's :func:`line_pixels`, when already computed (scoring several cameras on one frame).

    Returns:
        The shares, or None when fewer than ``min_points`` projected samples fall on grass.
    """
    H, W = image_bgr.shape[:2]
    lines, region = pixels if pixels is not None else line_pixels(image_bgr, config)
    projected = project_template(camera, curves, W, H, spacing_px=config.spacing_px)
    if not len(projected.uv_px):
        return None
    uv = np.round(projected.uv_px).astype(int)
    x, y = np.clip(uv[:, 0], 0, W - 1), np.clip(uv[:, 1], 0, H - 1)
    on_grass = region[y, x]
    if on_grass.sum() < config.min_points:
        return None
    x, y = x[on_grass], y[on_grass]
    r = max(2, int(round(W * config.tolerance_fraction)))
    marks = lines.astype(np.uint8)
    hit = _grown(marks, r)[y, x]
    visible = _grown(marks, int(round(config.visible_factor * r)))[y, x]
    counted = int(visible.sum())
    enough = counted >= max(1, config.min_visible_share * len(x))
    return Alignment(all_markings=float(hit.mean()),
                     visible_markings=float(hit[visible].mean()) if enough else 0.0,
                     samples=int(len(x)), visible_samples=counted)


def _grown(mask_u8: np.ndarray, radius_px: int) -> np.ndarray:
    """(H, W) bool: pixels within radius_px of a non-zero pixel of mask_u8."""
    size = 2 * radius_px + 1
    return cv2.dilate(mask_u8, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (size, size))) > 0
