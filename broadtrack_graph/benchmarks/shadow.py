"""A stand's shadow laid over real frames, for ``bench real --shadow``: does the tracker hold in shade?

Afternoon matches often have the shadow of a stand across part of the pitch. There the markings keep
only the share of their contrast that the shade keeps of the light: sky light alone against direct sun.
Where a clip has none, the bench lays one over every frame (:func:`lay_shadow`) and writes
the shaded copy of each clip (:func:`write_shadowed`, :mod:`.clip_copy`); the cameras tracked on the copy are
scored against the unshaded frames.

The shadow's edge is a straight line fixed in the image, a little right of the centre and leaning,
with a soft edge: a stand's shadow lies on the pitch and moves through the image as the camera
turns, so this tests what the detector sees in shade and across the edge, not the edge's motion.
Over a clip already in a stand's shadow it darkens the shade further, which no afternoon does.
"""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from broadtrack_graph.benchmarks.clip_copy import FrameChange, write_copy
from broadtrack_graph.errors import InputError

SHADOW_EDGE = (0.55, 0.6)
"""The shadow's edge: it crosses the image's middle row at this share of the width, and moves this many pixels right
per pixel up; the shade lies right of it."""
SHADOW_SOFT_EDGE_PER_WIDTH = 6.0 / 640
"""Gaussian width of the shadow's edge (a penumbra), as a share of the image width."""


def shadow_map(width_px: int, height_px: int) -> np.ndarray:
    """(H, W, 1) float32: 1 in the shade, 0 in the light, a soft edge between (module docstring)."""
    rows, cols = np.mgrid[0:height_px, 0:width_px].astype(np.float32)
    across, lean = SHADOW_EDGE
    inside = ((cols - across * width_px) + lean * (rows - height_px / 2.0) > 0).astype(np.float32)
    return cv2.GaussianBlur(inside, (0, 0), SHADOW_SOFT_EDGE_PER_WIDTH * width_px)[..., None]


def lay_shadow(image_bgr: np.ndarray, kept: float, shade: np.ndarray | None = None) -> np.ndarray:
    """The frame with the shadow laid over it.

    Args:
        image_bgr: (H, W, 3) uint8 frame.
        kept: the share of the light the shade keeps, in (0, 1].
        shade: :func:`shadow_map` of the frame's size (made when None).

    Returns:
        (H, W, 3) uint8: every pixel in the shade times ``kept`` (grey levels, as the camera gave them).
    """
    h, w = image_bgr.shape[:2]
    shade = shadow_map(w, h) if shade is None else shade
    return np.clip(np.rint(image_bgr * (1.0 - (1.0 - kept) * shade)), 0, 255).astype(np.uint8)


def shadow_change(kept: float) -> FrameChange:
    """The change laying the shadow over a frame (:func:`lay_shadow`; the shadow map made at the first frame's size).

    Raises:
        InputError: ``kept`` outside (0, 1].
    """
    if not 0.0 < kept <= 1.0:
        raise InputError(None, f"--shadow {kept}: the share of light kept in the shade must be in (0, 1]")
    shade: list = [None]

    def shaded(image: np.ndarray, _index: int) -> np.ndarray:
        if shade[0] is None or shade[0].shape[:2] != image.shape[:2]:
            shade[0] = shadow_map(image.shape[1], image.shape[0])
        return lay_shadow(image, kept, shade[0])

    return shaded


def write_shadowed(video: Path, out_path: Path, kept: float) -> int:
    """Write ``video`` with the shadow laid over every frame (mp4v, the source's size and rate), up to its first frame
    that cannot be decoded; returns the frames written.

    Raises:
        InputError: ``kept`` outside (0, 1], the video cannot be read (:class:`~broadtrack_graph.io.video.VideoSource`)
            or has no decodable frame, or the copy cannot be written.
    """
    return write_copy(video, out_path, shadow_change(kept))
