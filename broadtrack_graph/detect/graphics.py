"""Static broadcast graphics (score bug, channel logo, captions, sponsor overlays), found online and masked out.

Graphics are the pixels that stay put while the camera moves. On a small grey working
image, the global shift between consecutive frames is measured by phase correlation; each
time the camera has moved ``min_shift_px`` (working pixels) since the last sample, every
pixel votes: "static" when it matches the last sample at the same place but not where the
camera motion moved it, "moving" the other way round, no vote when both or neither match
(flat areas, edges parallel to the motion). Pixels whose recent votes (a running mean over
about ``1 / vote_weight`` votes, so an overlay that appears or goes away mid-clip is picked
up or dropped) are at least ``persistence`` static are graphics; they are closed into
blobs and each small blob is filled to its bounding box (the flat inside of a score bug
does not vote but is graphics too).

:func:`mask_graphics` removes the masked pixels from a frame's detections: marking points,
named line points, the marking map, and the field mask (which is the keep mask of optical
flow, so flow drops them too).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import cv2
import numpy as np

from broadtrack_graph.detect.detector import Detections, resize_mask
from broadtrack_graph.geometry.mask_blobs import blobs_with_stats


@dataclass(frozen=True)
class GraphicsConfig:
    """Settings of :class:`StaticGraphics` (pixel sizes at the working width)."""

    work_width_px: int = 160  # working width (pixels)
    same_grey: float = 6.0  # a pixel matches when it differs by less than this (grey levels) ...
    different_grey: float = 20.0  # ... and does not match when it differs by more than this
    min_shift_px: float = 3.0  # camera motion (working pixels) between two counted samples
    max_step_px: float = 20.0  # a larger shift between consecutive frames is a cut or a failed match: ignored
    min_samples: int = 8  # samples before anything is called graphics ...
    min_votes: int = 4  # ... and votes of the pixel
    persistence: float = 0.8  # share of static votes that makes a pixel graphics
    recent_samples: int = 15  # a pixel without a static vote in this many samples is not graphics (any more)
    vote_weight: float = 0.08  # weight of a new vote in the running share (a plain mean for the first votes)
    close_px: int = 9  # closing (working pixels) that joins an overlay's letters into one blob
    max_blob_share: float = 0.08  # a blob larger than this share of the image is not filled to its box
    dilate_px: int = 1  # margin added around the mask (working pixels)


class StaticGraphics:
    """Feed every frame in order with :meth:`update`; :attr:`mask` is the current graphics mask."""

    def __init__(self, config: GraphicsConfig = GraphicsConfig()) -> None:
        self.config = config
        self._prev: np.ndarray | None = None
        self._sample: np.ndarray | None = None  # the last counted frame (working grey)
        self._static: np.ndarray | None = None  # running share of static votes per pixel
        self._votes: np.ndarray | None = None  # votes per pixel
        self._last_static: np.ndarray | None = None  # sample number of each pixel's last static vote
        self._samples = 0
        self._moved = np.zeros(2)
        self.mask: np.ndarray | None = None  # (h, w) bool at the working size, or None while unknown

    @property
    def samples(self) -> int:
        """Frames counted so far (the camera had moved enough before each)."""
        return self._samples

    def update(self, image_bgr: np.ndarray) -> np.ndarray | None:
        """Add (H, W, 3) uint8 BGR ``image_bgr``; returns the (h, w) bool mask at the working size or None."""
        c = self.config
        H, W = image_bgr.shape[:2]
        h = max(1, int(round(H * c.work_width_px / W)))
        grey = cv2.cvtColor(cv2.resize(image_bgr, (c.work_width_px, h), interpolation=cv2.INTER_AREA),
                            cv2.COLOR_BGR2GRAY).astype(np.float32)
        if self._prev is None or self._prev.shape != grey.shape:
            self._prev, self._sample, self._samples = grey, grey, 0
            self._static, self._votes = np.zeros(grey.shape, np.float32), np.zeros(grey.shape, np.float32)
            self._last_static = np.full(grey.shape, -10**6, np.int64)
            self._moved[:] = 0.0
            self.mask = None
            return None
        (dx, dy), _ = cv2.phaseCorrelate(self._prev, grey)
        self._prev = grey
        step = np.array([dx, dy])
        if np.hypot(*step) > c.max_step_px:
            return self.mask
        self._moved += step
        if np.hypot(*self._moved) < c.min_shift_px:
            return self.mask
        sx, sy = self._moved
        self._moved[:] = 0.0
        h, w = grey.shape
        moved = cv2.warpAffine(self._sample, np.float32([[1, 0, sx], [0, 1, sy]]), (w, h),
                               borderMode=cv2.BORDER_REPLICATE)
        still = np.abs(cv2.blur(grey, (3, 3)) - cv2.blur(self._sample, (3, 3)))
        along = np.abs(cv2.blur(grey, (3, 3)) - cv2.blur(moved, (3, 3)))
        static = (still < c.same_grey) & (along > c.different_grey)
        moving = (along < c.same_grey) & (still > c.different_grey)
        vote = static | moving
        self._votes += vote
        weight = np.maximum(c.vote_weight, 1.0 / np.maximum(self._votes, 1.0))
        self._static += np.where(vote, weight * (static.astype(np.float32) - self._static), 0.0)
        self._sample = grey
        self._samples += 1
        self._last_static[static] = self._samples
        if self._samples >= c.min_samples:
            self.mask = self._mask()
        return self.mask

    def _mask(self) -> np.ndarray:
        c = self.config
        static = ((self._static >= c.persistence) & (self._votes >= c.min_votes)
                  & (self._samples - self._last_static <= c.recent_samples)).astype(np.uint8) * 255
        kernel = cv2.getStructuringElement(cv2.MORPH_RECT, (c.close_px, c.close_px))
        blobs = cv2.morphologyEx(static, cv2.MORPH_CLOSE, kernel)
        count, labels, stats, _ = blobs_with_stats(blobs > 0)
        out = blobs > 0
        for i in range(1, count):
            x, y, w, h, area = stats[i]
            if w * h <= c.max_blob_share * blobs.size and area >= 4:
                out[y:y + h, x:x + w] = True
            elif area < 4:
                out[labels == i] = False
        if c.dilate_px > 0 and out.any():
            k = 2 * c.dilate_px + 1
            out = cv2.dilate(out.astype(np.uint8), cv2.getStructuringElement(cv2.MORPH_RECT, (k, k))) > 0
        return out


def mask_graphics(detections: Detections, mask: np.ndarray | None) -> Detections:
    """The detections without what lies under graphics.

    Args:
        detections: one frame's detections (points in frame pixels, masks at any size).
        mask: (h, w) bool graphics mask at any size (scaled to each mask's size), or None.

    Returns:
        new Detections (the input is not changed); the same object when the mask is None or empty.
    """
    if mask is None or not mask.any():
        return detections
    W, H = detections.width_px, detections.height_px

    def outside(points_px: np.ndarray) -> np.ndarray:
        points_px = np.asarray(points_px, float).reshape(-1, 2)
        if not len(points_px):
            return points_px
        mh, mw = mask.shape
        x = np.clip(((points_px[:, 0] + 0.5) * mw / W).astype(int), 0, mw - 1)
        y = np.clip(((points_px[:, 1] + 0.5) * mh / H).astype(int), 0, mh - 1)
        return points_px[~mask[y, x]]

    clear: dict = {}  # (h, w) -> where no graphics lie at that size (the masks share one size: resized once)

    def cut(image_mask: np.ndarray | None) -> np.ndarray | None:
        if image_mask is None:
            return None
        h, w = image_mask.shape
        if (h, w) not in clear:
            clear[h, w] = ~resize_mask(mask, w, h)
        return image_mask & clear[h, w]

    return replace(detections, lines_px={name: outside(p) for name, p in detections.lines_px.items()},
                   marking_points_px=outside(detections.marking_points_px),
                   marking_mask=cut(detections.marking_mask), field_mask=cut(detections.field_mask))
