"""Does a frame show the tracked (main, wide) camera's view, or another view?

Measured on a 160-pixel-wide working image:
- the grass share (HSV range of playing surface); a main-camera frame is mostly pitch;
- inside the grass region (the convex hull of the largest grass component), the non-grass
  blobs left after an opening that removes thin markings: a main camera shows players a
  few percent of the image high; a close-up shows one body covering a large part of it.

A frame with too little grass is "crowd" (stands, bench, studio, graphics); one with a
huge blob on grass is "close-up"; otherwise "main". The zoom of a replay or another wide
camera is not told apart here: those are re-initialised like the main camera and the
tracker's confidence decides.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from broadtrack_graph.geometry.mask_blobs import blobs_with_stats

VIEW_MAIN = "main"
VIEW_CLOSE_UP = "close-up"
VIEW_CROWD = "crowd"
VIEWS = (VIEW_MAIN, VIEW_CLOSE_UP, VIEW_CROWD)


@dataclass(frozen=True)
class ViewConfig:
    """Settings of :func:`classify_view`."""

    work_width_px: int = 160  # working width (pixels)
    grass_hue_min: int = 30  # OpenCV hue (0..180) range of grass
    grass_hue_max: int = 95
    grass_min_saturation: int = 40
    grass_min_value: int = 30
    min_grass_share: float = 0.25  # less grass than this share of the image: not the main camera
    blob_open_px: int = 3  # opening (working pixels) that removes markings from the non-grass mask
    max_blob_height: float = 0.45  # a non-grass blob on the grass taller than this share of the image height: close-up
    max_blob_share: float = 0.05  # ... or larger than this share of the image and ...
    min_big_blob_height: float = 0.25  # ... taller than this (a caption bar is wide, not tall)
    max_hull_other_share: float = 0.35  # non-grass share inside the grass hull above this: not the main camera


@dataclass(frozen=True)
class ViewResult:
    """One frame's view.

    kind: one of :data:`VIEWS`.
    reason: one line (the measured figures).
    grass_share: share of the image that is grass (0..1).
    blob_share: the largest non-grass blob on the grass, as a share of the image (0..1).
    """

    kind: str
    reason: str
    grass_share: float
    blob_share: float

    @property
    def is_main(self) -> bool:
        return self.kind == VIEW_MAIN


def grass_mask(small_bgr: np.ndarray, config: ViewConfig) -> np.ndarray:
    """(h, w) uint8 0/255 mask of grass-coloured pixels."""
    hsv = cv2.cvtColor(small_bgr, cv2.COLOR_BGR2HSV)
    return cv2.inRange(hsv, (config.grass_hue_min, config.grass_min_saturation, config.grass_min_value),
                       (config.grass_hue_max, 255, 255))


def row_ends(mask: np.ndarray) -> np.ndarray:
    """(K, 2) int32 (x, y) of the first and the last pixel of each row of a (h, w) bool mask that has one: their
    convex hull is the mask's (a row's other pixels lie between its two ends), from at most 2h points instead of
    every pixel of a field-sized region."""
    rows = np.flatnonzero(mask.any(axis=1))
    if not len(rows):
        return np.zeros((0, 2), np.int32)
    kept = mask[rows]
    first = np.argmax(kept, axis=1)
    last = mask.shape[1] - 1 - np.argmax(kept[:, ::-1], axis=1)
    return np.concatenate([np.column_stack([first, rows]), np.column_stack([last, rows])]).astype(np.int32)


def classify_view(image_bgr: np.ndarray, config: ViewConfig = ViewConfig()) -> ViewResult:
    """Classify one (H, W, 3) uint8 BGR frame (see the module docstring)."""
    H, W = image_bgr.shape[:2]
    w = config.work_width_px
    h = max(1, int(round(H * w / W)))
    small = cv2.resize(image_bgr, (w, h), interpolation=cv2.INTER_AREA)
    grass = grass_mask(small, config)
    grass_share = float(np.count_nonzero(grass)) / grass.size
    if grass_share < config.min_grass_share:
        return ViewResult(VIEW_CROWD, f"grass share {grass_share:.2f} below {config.min_grass_share:.2f}",
                          grass_share, 0.0)
    count, labels, stats, _ = blobs_with_stats(grass > 0)
    largest = 1 + int(np.argmax(stats[1:, cv2.CC_STAT_AREA]))
    hull = cv2.convexHull(row_ends(labels == largest))
    region = np.zeros_like(grass)
    cv2.fillConvexPoly(region, hull, 255)
    other = cv2.bitwise_and(cv2.bitwise_not(grass), region)
    k = config.blob_open_px
    other = cv2.morphologyEx(other, cv2.MORPH_OPEN, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (k, k)))
    hull_area = max(1, int(np.count_nonzero(region)))
    hull_other = float(np.count_nonzero(other)) / hull_area
    blob_share, blob_height = 0.0, 0.0
    count, labels, stats, _ = blobs_with_stats(other > 0)
    if count > 1:
        i = 1 + int(np.argmax(stats[1:, cv2.CC_STAT_AREA]))
        blob_share = float(stats[i, cv2.CC_STAT_AREA]) / grass.size
        blob_height = float(stats[i, cv2.CC_STAT_HEIGHT]) / h
    figures = f"grass {grass_share:.2f}, largest blob {blob_share:.3f} of the image ({blob_height:.2f} high)"
    if blob_height > config.max_blob_height or (blob_share > config.max_blob_share
                                                and blob_height > config.min_big_blob_height):
        return ViewResult(VIEW_CLOSE_UP, f"close-up: {figures}", grass_share, blob_share)
    if hull_other > config.max_hull_other_share:
        return ViewResult(VIEW_CLOSE_UP, f"close-up: non-grass {hull_other:.2f} of the grass region; {figures}",
                          grass_share, blob_share)
    return ViewResult(VIEW_MAIN, figures, grass_share, blob_share)
