"""Turn what the user gives (frames, a detections file, or both) into the tracking loop's frames."""

from __future__ import annotations

import logging
from pathlib import Path
from typing import Iterator

import cv2
import numpy as np

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.detections import DetectionsFile
from broadtrack_graph.io.frames import FrameSource
from broadtrack_graph.observations import FrameObservations
from broadtrack_graph.pipeline import FrameInput

log = logging.getLogger(__name__)


def frames_from_source(source: FrameSource) -> Iterator[FrameInput]:
    """Image input: one FrameInput per frame of the source (missing frames carry their problem)."""
    for frame in source:
        yield FrameInput(frame.frame_index, frame.frame_id, frame.time_s, frame.image_bgr, None, frame.problem)


def frames_from_detections(detections: DetectionsFile, fps: float = 25.0, start: int | None = None,
                           end: int | None = None, source: FrameSource | None = None) -> Iterator[FrameInput]:
    """Detections-file input, optionally with the frames (which turn optical flow on).

    Frames the file does not mention get empty observations (tracked through on the
    motion prior and reported). With a frame source, its frames set the range and ids.
    """
    if detections.image_size is None:
        raise InputError(None, "detections file states no image size")
    width, height = detections.image_size
    if source is not None:
        if (source.width_px, source.height_px) != (width, height):
            log.warning("detections are for %dx%d, frames are %dx%d: coordinates are rescaled",
                        width, height, source.width_px, source.height_px)
        for frame in source:
            observations = detections.frames.get(frame.frame_index)
            if observations is None:
                observations = FrameObservations(frame.frame_index, width, height)
            yield FrameInput(frame.frame_index, frame.frame_id, frame.time_s, frame.image_bgr, observations,
                             frame.problem if frame.image_bgr is None else None)
        return
    first = 0 if start is None else start
    last = detections.last_frame + 1 if end is None else min(end, detections.last_frame + 1)
    for index in range(first, last):
        observations = detections.frames.get(index) or FrameObservations(index, width, height)
        frame_id = detections.frame_ids.get(index, f"{index + 1:06d}")
        yield FrameInput(index, frame_id, index / fps, None, observations)


def read_mask(path: Path, width_px: int, height_px: int) -> np.ndarray | None:
    """A binary marking mask image from a detections file, at (W, H); None (with a warning) if unreadable."""
    mask = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
    if mask is None:
        log.warning("%s: marking mask cannot be read; ignored", path)
        return None
    if mask.shape != (height_px, width_px):
        mask = cv2.resize(mask, (width_px, height_px), interpolation=cv2.INTER_NEAREST)
    return mask > 127
