"""Annotate the loop's frames with their shot (cut, view, camera id) and the static graphics mask.

Runs where the frames are decoded (a thread or a process of their own: :mod:`broadtrack_graph.track.ahead`),
one frame at a time in order, so it adds no latency: both the shot step and
the graphics mask look only at the current and past frames.
"""

from __future__ import annotations

import logging
from typing import Callable, Iterable, Iterator

import cv2
import numpy as np

from broadtrack_graph.detect.graphics import GraphicsConfig, StaticGraphics
from broadtrack_graph.shots.segmenter import ShotConfig, ShotSegmenter
from broadtrack_graph.track.inputs import FrameInput

log = logging.getLogger(__name__)

WORK_WIDTH_PX = 160
"""Width (pixels) the frame is reduced to before the shot step and the graphics mask (both work at <= 160)."""


class ShotStream:
    """Wraps an iterable of :class:`FrameInput`; :attr:`segmenter` keeps the shots seen so far.

    Args:
        frames: the loop's frames (image input; frames without an image pass through).
        shots: shot settings, or None to skip shot detection.
        graphics: graphics-mask settings, or None to skip it.
        reduce: ``image -> the detector's working image, or None`` when that is no area reduction of the frame
            (:meth:`~broadtrack_graph.detect.weightfree.WeightFreeDetector.area_working_image`); None: not made.
            Made once here (``FrameInput.working_bgr``, for the detector), the thumbnail is reduced from it.
    """

    def __init__(self, frames: Iterable[FrameInput], shots: ShotConfig | None = ShotConfig(),
                 graphics: GraphicsConfig | None = GraphicsConfig(),
                 reduce: Callable[[np.ndarray], np.ndarray | None] | None = None) -> None:
        self.frames = frames
        self.reduce = reduce
        self.segmenter = ShotSegmenter(shots) if shots is not None else None
        self.graphics = StaticGraphics(graphics) if graphics is not None else None

    def __iter__(self) -> Iterator[FrameInput]:
        for frame in self.frames:
            if frame.image is not None:
                # Both steps work on small images: reduce the frame once (area averaging), from the detector's
                # working image when it is one.
                if self.reduce is not None and frame.working_bgr is None:
                    frame.working_bgr = self.reduce(frame.image)
                source = frame.image if frame.working_bgr is None else frame.working_bgr
                H, W = source.shape[:2]
                width = min(W, WORK_WIDTH_PX)
                small = cv2.resize(source, (width, max(1, int(round(H * width / W)))), interpolation=cv2.INTER_AREA)
                if self.segmenter is not None:
                    frame.shot = self.segmenter.update(frame.frame_index, small)
                if self.graphics is not None:
                    frame.graphics_mask = self.graphics.update(small)
            elif self.segmenter is not None:
                self.segmenter.update(frame.frame_index, None)
            yield frame

    @classmethod
    def for_run(cls, frames: Iterable[FrameInput], detect_shots: bool, mask_graphics: bool,
                detector=None) -> "ShotStream":
        """A run's stream: shots and the graphics mask as its options say (default settings), the working image
        made with the detector's ``area_working_image`` when it has one."""
        return cls(frames, ShotConfig() if detect_shots else None, GraphicsConfig() if mask_graphics else None,
                   getattr(detector, "area_working_image", None))

    @property
    def detects_shots(self) -> bool:
        """Whether shots are looked for (shot settings given)."""
        return self.segmenter is not None

    @property
    def shots(self) -> list:
        """The shots so far (:class:`~broadtrack_graph.types.shot.Shot`), empty without shot detection."""
        return [] if self.segmenter is None else self.segmenter.shots
