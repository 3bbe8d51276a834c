"""In-memory clips (tests, synthetic clips) as a frame source."""

from __future__ import annotations

from typing import Iterator, Sequence

import numpy as np

from broadtrack_graph.io.frame_source import DEFAULT_FPS, Frame, FrameSource, frame_window
from broadtrack_graph.io.video import VideoSource


class ArrayFrameSource(FrameSource):
    """An in-memory clip (tests, synthetic clips): a sequence of BGR images or None.

    Args:
        images: sequence of (H, W, 3) uint8 images (None entries are yielded as missing).
        fps: frame rate for time_s.
        frame_ids: ids per image (default 1-based 6-digit, as for videos).
        start, end: window (end exclusive).
    """

    kind = "in-memory"

    def __init__(
        self,
        images: Sequence[np.ndarray | None],
        fps: float = DEFAULT_FPS,
        frame_ids: Sequence[str] | None = None,
        start: int | None = None,
        end: int | None = None,
    ) -> None:
        super().__init__()
        self.images = images
        self.frame_ids = list(frame_ids) if frame_ids is not None else [VideoSource.frame_id_of(i) for i in range(len(images))]
        if len(self.frame_ids) != len(images):
            raise ValueError(f"frame_ids has {len(self.frame_ids)} entries for {len(images)} images")
        first = next((im for im in images if im is not None), None)
        if first is None:
            raise ValueError("in-memory clip has no image")
        self.height_px, self.width_px = first.shape[:2]
        self.fps = float(fps)
        self.start, self.end = frame_window(start, end, len(images), "<in-memory clip>")

    def __iter__(self) -> Iterator[Frame]:
        for index in range(self.start, self.end):
            image = self.images[index]
            problem = "missing frame" if image is None else self._check_size(image)
            yield Frame(index, self.frame_ids[index], self._time(index), None if problem else image, problem)
