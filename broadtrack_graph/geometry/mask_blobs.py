"""The 8-connected blobs of a binary mask with their boxes and areas, fast. No I/O.

``cv2.connectedComponentsWithStats`` with OpenCV's default algorithm takes 0.66 ms on a 480x270 player mask at one
thread; Grana's block-based labelling (``cv2.CCL_GRANA``) gives the same labels, numbered in the same raster order,
and the same stats in 0.25 ms. The detector labels several masks a frame, so every caller goes through here.
"""

from __future__ import annotations

import cv2
import numpy as np


def blobs_with_stats(mask: np.ndarray) -> tuple[int, np.ndarray, np.ndarray, np.ndarray]:
    """The 8-connected blobs of a mask, as ``cv2.connectedComponentsWithStats(mask, connectivity=8)``.

    Args:
        mask: (h, w) uint8 (or bool), non-zero on the blobs.

    Returns:
        count: K + 1 (label 0 is the background); labels: (h, w) int32; stats: (K + 1, 5) int32 left, top, width,
        height, area (pixels; ``cv2.CC_STAT_*``); centroids: (K + 1, 2) float64 (x, y) pixels.
    """
    if mask.dtype != np.uint8:
        mask = mask.astype(np.uint8)
    return cv2.connectedComponentsWithStatsWithAlgorithm(mask, 8, cv2.CV_32S, cv2.CCL_GRANA)
