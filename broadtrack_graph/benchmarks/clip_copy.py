"""A real clip's copy changed frame by frame, for ``bench real``'s ``--shadow`` and ``--degrade``.

The copy is written under the bench's work folder, never in the repository (the clips are copyrighted), and keeps
the clip's frame indices: it ends where decoding does.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path

import numpy as np

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.video import VideoSource, open_video_writer

FrameChange = Callable[[np.ndarray, int], np.ndarray]
"""``change(image_bgr (H, W, 3) uint8, frame index) -> the copy's frame (h, w, 3) uint8``, one size for every frame."""


def write_copy(video: Path, out_path: Path, change: FrameChange) -> int:
    """Write ``change`` of every frame of ``video`` (mp4v, the source's rate, the changed frames' size) up to its first
    frame that cannot be decoded; returns the frames written.

    Raises:
        InputError: the video cannot be read (:class:`~broadtrack_graph.io.video.VideoSource`) or has no decodable
            frame, or the copy cannot be written.
    """
    frames, writer = 0, None
    with VideoSource(video) as source:
        try:
            for frame in source:
                if frame.image_bgr is None:
                    break
                changed = change(frame.image_bgr, frame.frame_index)
                if writer is None:
                    writer = open_video_writer(out_path, source.fps, (changed.shape[1], changed.shape[0]))
                writer.write(changed)
                frames += 1
        finally:
            if writer is not None:
                writer.release()
    if frames == 0:
        raise InputError(video, "no frame could be decoded")
    return frames


def chained(*changes: FrameChange) -> FrameChange:
    """One change made of several, applied in order (a shadow laid, then the frame degraded)."""

    def change(image: np.ndarray, index: int) -> np.ndarray:
        for one in changes:
            image = one(image, index)
        return image

    return change
