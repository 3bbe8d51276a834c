"""Online detection of hard cuts and short dissolves from colour histograms of a thumbnail.

Per frame: a 64-pixel-wide thumbnail, its HSV histogram (hue x saturation x value bins,
sum 1) and its grey image. A hard cut is a histogram distance (half the L1 distance, 0..1)
to the previous frame far above the recent ones (adaptive threshold: a floor, and a multiple
of the median of the last frames), or a grey thumbnail change far above the recent ones
with a clear histogram change. A dissolve is a large histogram distance over
``dissolve_frames`` frames made of moderate steps, whose middle thumbnail is close to the
mean of its ends (a blend). Both are decided from the current and past frames only (the
dissolve is reported at its last frame), so the detector runs online.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import cv2
import numpy as np


@dataclass(frozen=True)
class CutConfig:
    """Settings of :class:`CutDetector`."""

    thumb_width_px: int = 64  # thumbnail width (pixels); the height keeps the aspect ratio
    hue_bins: int = 12  # histogram bins of hue (OpenCV 0..180) ...
    saturation_bins: int = 4  # ... saturation ...
    value_bins: int = 4  # ... and value
    cut_min_distance: float = 0.30  # a hard cut needs at least this histogram distance (0..1) ...
    cut_median_factor: float = 4.0  # ... and this many times the median of the recent distances
    pixel_cut_min: float = 15.0  # or a mean grey change (grey levels) of at least this ...
    pixel_median_factor: float = 6.0  # ... and this many times its recent median ...
    pixel_cut_hist_min: float = 0.10  # ... with at least this histogram distance ...
    pixel_cut_hist_factor: float = 3.0  # ... and this many times its recent median
    history_frames: int = 15  # recent frames for the adaptive thresholds
    dissolve_frames: int = 6  # span of a dissolve check (frames)
    dissolve_min_distance: float = 0.35  # histogram distance over the span
    dissolve_blend_ratio: float = 0.5  # middle-to-mean change below this share of the end-to-end change
    min_shot_frames: int = 2  # no second boundary closer than this to the previous one (a flash is one cut) ...
    strong_cut_distance: float = 0.6  # ... unless the histogram distance is at least this (a short cut-away)


@dataclass(frozen=True)
class CutResult:
    """One frame's boundary decision.

    cut: True when this frame starts a new shot.
    kind: "hard", "dissolve" or None.
    distance: histogram distance (0..1) to the previous frame, or None for the first frame.
    """

    cut: bool
    kind: str | None
    distance: float | None


def thumbnail(image_bgr: np.ndarray, width_px: int) -> np.ndarray:
    """(h, width_px, 3) uint8 BGR thumbnail (area averaging)."""
    H, W = image_bgr.shape[:2]
    height = max(1, int(round(H * width_px / W)))
    return cv2.resize(image_bgr, (width_px, height), interpolation=cv2.INTER_AREA)


def colour_histogram(thumb_bgr: np.ndarray, config: CutConfig) -> np.ndarray:
    """(hue_bins * saturation_bins * value_bins,) HSV histogram of a thumbnail, summing to 1."""
    hsv = cv2.cvtColor(thumb_bgr, cv2.COLOR_BGR2HSV)
    hist = cv2.calcHist([hsv], [0, 1, 2], None, [config.hue_bins, config.saturation_bins, config.value_bins],
                        [0, 180, 0, 256, 0, 256]).ravel()
    return hist / max(hist.sum(), 1.0)


def histogram_distance(a: np.ndarray, b: np.ndarray) -> float:
    """Half the L1 distance of two histograms summing to 1 (0 same, 1 disjoint)."""
    return 0.5 * float(np.abs(a - b).sum())


class CutDetector:
    """Feed frames in order with :meth:`update`; each call says whether that frame starts a new shot."""

    def __init__(self, config: CutConfig = CutConfig()) -> None:
        self.config = config
        self._hists: deque[np.ndarray] = deque(maxlen=config.dissolve_frames + 1)
        self._greys: deque[np.ndarray] = deque(maxlen=config.dissolve_frames + 1)
        self._distances: deque[float] = deque(maxlen=config.history_frames)
        self._changes: deque[float] = deque(maxlen=config.history_frames)
        self._since_cut = 0

    def reset(self) -> None:
        """Forget the past (the next frame starts a shot)."""
        self._hists.clear()
        self._greys.clear()
        self._distances.clear()
        self._changes.clear()
        self._since_cut = 0

    def update(self, image_bgr: np.ndarray) -> CutResult:
        """Decide whether (H, W, 3) uint8 BGR ``image_bgr`` starts a new shot."""
        c = self.config
        thumb = thumbnail(image_bgr, c.thumb_width_px)
        hist = colour_histogram(thumb, c)
        grey = cv2.cvtColor(thumb, cv2.COLOR_BGR2GRAY).astype(np.float32)
        if not self._hists or self._greys[-1].shape != grey.shape:
            self.reset()
            self._push(hist, grey)
            return CutResult(True, "hard", None)
        distance = histogram_distance(hist, self._hists[-1])
        change = float(np.abs(grey - self._greys[-1]).mean())
        median_d = float(np.median(self._distances)) if self._distances else 0.0
        median_c = float(np.median(self._changes)) if self._changes else 0.0
        self._since_cut += 1
        kind = None
        if self._since_cut >= c.min_shot_frames or distance >= c.strong_cut_distance:
            if distance >= max(c.cut_min_distance, c.cut_median_factor * median_d):
                kind = "hard"
            elif change >= max(c.pixel_cut_min, c.pixel_median_factor * median_c) and \
                    distance >= max(c.pixel_cut_hist_min, c.pixel_cut_hist_factor * median_d):
                kind = "hard"
            elif self._is_dissolve(hist, grey):
                kind = "dissolve"
        if kind is not None:
            # A new shot: its own statistics start now.
            self.reset()
            self._push(hist, grey)
            return CutResult(True, kind, distance)
        self._distances.append(distance)
        self._changes.append(change)
        self._push(hist, grey)
        return CutResult(False, None, distance)

    def _push(self, hist: np.ndarray, grey: np.ndarray) -> None:
        self._hists.append(hist)
        self._greys.append(grey)

    def _is_dissolve(self, hist: np.ndarray, grey: np.ndarray) -> bool:
        c = self.config
        k = c.dissolve_frames
        if len(self._hists) < k or self._since_cut < k:
            return False
        first_hist, first_grey = self._hists[-k], self._greys[-k]
        if histogram_distance(hist, first_hist) < c.dissolve_min_distance:
            return False
        middle = self._greys[-(k // 2)]
        end_to_end = float(np.abs(grey - first_grey).mean())
        blend = float(np.abs(middle - 0.5 * (grey + first_grey)).mean())
        return end_to_end > 1e-6 and blend < c.dissolve_blend_ratio * 0.5 * end_to_end
