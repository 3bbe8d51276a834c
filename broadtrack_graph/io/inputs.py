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
    first = min(detections.frames) if start is None else start  # a file written with --start begins there
    last = detections.last_frame + 1 if end is None else min(end, detections.last_frame + 1)
    for index in range(first, last):
        observations = detections.frames.get(index) or FrameObservations(index, width, height)
        frame_id = detections.frame_ids.get(index, f"{index + 1:06d}")
        yield FrameInput(index, frame_id, index / fps, None, observations)


def read_mask(path: Path, width_px: int, height_px: int) -> tuple[np.ndarray, np.ndarray | None] | None:
    """A marking mask image of a detections file, at (W, H): (markings, field or None).

    Markings are pixels above 127; when the image also has pixels in 1..127 they mark the
    playing surface (``detect`` writes 255 on markings, 64 on the rest of the field).
    None (with a warning) when the image cannot be read.
    """
    grey = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
    if grey is None:
        log.warning("%s: marking mask cannot be read; ignored", path)
        return None
    if grey.shape != (height_px, width_px):
        grey = cv2.resize(grey, (width_px, height_px), interpolation=cv2.INTER_NEAREST)
    markings = grey > 127
    has_field = bool(np.any((grey > 0) & (grey <= 127)))
    return markings, (grey > 0) if has_field else None
