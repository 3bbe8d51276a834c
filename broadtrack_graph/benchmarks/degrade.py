"""A real clip as a lower-league feed or a web stream gives it, for ``bench real --degrade W:Q:N``.

A small ground's broadcast or a re-encoded stream has fewer pixels, sensor noise and blocky compression: each frame
is area-reduced to ``W`` pixels wide (the height in proportion, even), given Gaussian noise of ``N`` grey levels
(the same noise for the same frame index: a run is repeatable) and compressed as a JPEG of quality ``Q`` (1-100)
(:func:`degrade_frame`). The copy is written by :mod:`.clip_copy`; the cameras tracked on it are scored on the
original frames, at their size.
"""

from __future__ import annotations

import argparse
from dataclasses import dataclass

import cv2
import numpy as np

from broadtrack_graph.benchmarks.clip_copy import FrameChange

NOISE_STREAM = 2711
"""Random stream of the noise (numpy SeedSequence entropy [NOISE_STREAM, frame index])."""


@dataclass(frozen=True)
class Degradation:
    """width_px: the copy's width (at most the frame's; the height in proportion, even); jpeg_quality: 1-100;
    noise_sigma: Gaussian noise, grey levels (0: none)."""

    width_px: int
    jpeg_quality: int
    noise_sigma: float

    @property
    def label(self) -> str:
        """Its part of the copy's name, e.g. ``854px-q25-n3``."""
        return f"{self.width_px}px-q{self.jpeg_quality}-n{self.noise_sigma:g}"


def parse_degradation(text: str) -> Degradation:
    """``W:Q:N`` (e.g. ``854:25:3``) as a :class:`Degradation`; an ``argparse`` type."""
    parts = text.split(":")
    try:
        width, quality, noise = int(parts[0]), int(parts[1]), float(parts[2])
    except (IndexError, ValueError):
        raise argparse.ArgumentTypeError(f"'{text}' is not W:Q:N (width in pixels, JPEG quality 1-100, noise in "
                                         "grey levels), e.g. 854:25:3") from None
    if len(parts) != 3 or not 16 <= width <= 16384 or not 1 <= quality <= 100 or not 0.0 <= noise <= 64.0:
        raise argparse.ArgumentTypeError(f"'{text}': give a width of 16 .. 16384 px, a JPEG quality of 1 .. 100 and "
                                         "a noise of 0 .. 64 grey levels")
    return Degradation(width, quality, noise)


def degrade_frame(image_bgr: np.ndarray, degradation: Degradation, frame_index: int = 0) -> np.ndarray:
    """The frame as the degraded feed shows it (module docstring).

    Args:
        image_bgr: (H, W, 3) uint8.

    Returns:
        (h, w, 3) uint8 with w = min(W, ``width_px``) and h = H w / W rounded to an even number (at least 2).
    """
    H, W = image_bgr.shape[:2]
    w = min(W, degradation.width_px)
    h = max(2, int(round(H * w / W / 2.0)) * 2)
    small = image_bgr if (w, h) == (W, H) else cv2.resize(image_bgr, (w, h), interpolation=cv2.INTER_AREA)
    if degradation.noise_sigma > 0:
        rng = np.random.default_rng([NOISE_STREAM, frame_index])
        noisy = small.astype(np.float32) + rng.normal(0.0, degradation.noise_sigma, small.shape).astype(np.float32)
        small = np.clip(np.rint(noisy), 0, 255).astype(np.uint8)
    ok, encoded = cv2.imencode(".jpg", small, [cv2.IMWRITE_JPEG_QUALITY, degradation.jpeg_quality])
    return cv2.imdecode(encoded, cv2.IMREAD_COLOR) if ok else small


def degrade_change(degradation: Degradation) -> FrameChange:
    """:func:`degrade_frame` as a :data:`~.clip_copy.FrameChange`."""
    return lambda image, index: degrade_frame(image, degradation, index)
