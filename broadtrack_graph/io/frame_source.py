"""The frame-source interface: :class:`Frame` (one decoded frame or a missing one) and
:class:`FrameSource` (iterate, ``len``, context manager), plus the ``start``/``end`` window check.

The conventions (frame_index, frame_id, time_s, missing frames) are described in
:mod:`broadtrack_graph.io.frames`.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

import numpy as np

from broadtrack_graph.errors import InputError

DEFAULT_FPS = 25.0
"""Frame rate assumed for image folders that do not state one (SoccerNet clips are 25 fps)."""


@dataclass(frozen=True)
class Frame:
    """One frame of a clip.

    frame_index: 0-based position in the whole input.
    frame_id: image file stem, or the 1-based 6-digit position for videos.
    time_s: frame_index / fps, seconds.
    image_bgr: (H, W, 3) uint8 BGR image, or None when the frame could not be read.
    problem: why image_bgr is None (one line), else None.
    """

    frame_index: int
    frame_id: str
    time_s: float
    image_bgr: np.ndarray | None
    problem: str | None = None

    @property
    def is_missing(self) -> bool:
        return self.image_bgr is None


class FrameSource:
    """Common interface of the frame sources (iterate, ``len``, context manager).

    Attributes:
        path: the input (file or folder); None for in-memory clips.
        width_px, height_px: size of every yielded image.
        fps: frames per second used for time_s.
        start, end: the window of frame indices yielded (end exclusive).
    """

    kind = "abstract"

    def __init__(self) -> None:
        self.path: Path | None = None
        self.width_px = 0
        self.height_px = 0
        self.fps = DEFAULT_FPS
        self.start = 0
        self.end = 0

    def __len__(self) -> int:
        """Number of frames the iteration yields (for videos: as the container states it)."""
        return max(0, self.end - self.start)

    def __iter__(self) -> Iterator[Frame]:
        raise NotImplementedError

    def close(self) -> None:
        """Release the underlying reader (no-op for folders)."""

    def __enter__(self) -> "FrameSource":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def describe(self) -> dict:
        """Plain-data description for run summaries."""
        return {
            "kind": self.kind, "path": None if self.path is None else str(self.path), "width_px": self.width_px,
            "height_px": self.height_px, "fps": self.fps, "start": self.start, "end": self.end, "frames": len(self),
        }

    def _time(self, frame_index: int) -> float:
        return frame_index / self.fps

    def _check_size(self, image: np.ndarray) -> str | None:
        if image.shape[0] != self.height_px or image.shape[1] != self.width_px:
            return f"image is {image.shape[1]}x{image.shape[0]}, the clip is {self.width_px}x{self.height_px}"
        return None


def frame_window(start: int | None, end: int | None, count: int, path) -> tuple[int, int]:
    """Validate --start/--end against the clip length; returns (start, end) with end exclusive."""
    start = 0 if start is None else int(start)
    end = count if end is None else min(int(end), count)
    if start < 0:
        raise InputError(path, f"--start must be >= 0, got {start}")
    if start >= count:
        raise InputError(path, f"--start {start} is past the end of the input ({count} frames)")
    if end <= start:
        raise InputError(path, f"--end {end} must be greater than --start {start}")
    return start, end
