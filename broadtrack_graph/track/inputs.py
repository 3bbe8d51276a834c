"""Turn what the user gives (frames, a detections file, or both) into the tracking loop's frames."""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator

import numpy as np

from broadtrack_graph.detect.detector import Detections
from broadtrack_graph.errors import InputError
from broadtrack_graph.io.decode_summary import decodable_frames
from broadtrack_graph.io.detections import DetectionsFile
from broadtrack_graph.io.frame_source import FrameSource
from broadtrack_graph.io.mask_png import read_mask_png
from broadtrack_graph.track.detection_frames import bound_by_gap, bound_to_window
from broadtrack_graph.types.observations import FrameObservations

log = logging.getLogger(__name__)


@dataclass
class FrameInput:
    """One frame as the loop sees it: image and/or precomputed observations."""

    frame_index: int
    frame_id: str
    time_s: float | None
    image: np.ndarray | None = None
    observations: FrameObservations | None = None  # from a detections file
    problem: str | None = None  # why the frame is missing
    flow_frame: object | None = None  # prepared for optical flow (frontend.flow.prepare), when done ahead
    shot: object | None = None  # shots.segmenter.FrameShot: cut, view kind and camera id, when shots are detected
    graphics_mask: np.ndarray | None = None  # (h, w) bool static broadcast graphics at any size, or None
    markings: object | None = None  # detect.found_markings.FoundMarkings: the camera-free half of detection, done ahead
    flow_ahead: object | None = None  # detect.flow.FlowCandidates from the previous frame, done ahead (no camera yet)
    repeats_previous: bool = False  # the image is the previous frame's again (shots.repeats), found ahead
    working_bgr: np.ndarray | None = None  # the detector's colour working image when it is an area reduction of the
    #                                        image (detect.weightfree.WeightFreeDetector.area_working_image), made once
    image_stayed: bool = False  # decoded and prepared in the preparing process, its pixels not sent: the loop reads
    #                             its markings and flow frame only (track.ahead.without_pixels)

    @property
    def shows_other_view(self) -> bool:
        """Whether the shot step found the frame showing another view than a pitch camera's (not tracked)."""
        return self.shot is not None and self.shot.is_other_view

    @property
    def has_image(self) -> bool:
        """Whether the frame was decoded (its image here, or left where it was prepared)."""
        return self.image is not None or self.image_stayed


def frames_from_source(source: FrameSource) -> Iterator[FrameInput]:
    """Image input: one FrameInput per frame of the source (missing frames carry their problem).

    A video's undecodable tail (a container stating more frames than it holds) is dropped with
    one summary line (:func:`~broadtrack_graph.io.decode_summary.drop_undecodable_tail`).
    """
    for frame in decodable_frames(source):
        yield FrameInput(frame.frame_index, frame.frame_id, frame.time_s, frame.image_bgr, None, frame.problem)


def frames_from_detections(detections: DetectionsFile, fps: float = 25.0, start: int | None = None,
                           end: int | None = None, source: FrameSource | None = None) -> Iterator[FrameInput]:
    """Detections-file input, optionally with the frames (which turn optical flow on).

    Frames the file does not mention get empty observations (carried on the motion prior for
    a bounded number of frames, status ``motion-prior``, then ``no-detections``). With a frame
    source, its frames set the range and ids and records outside them are dropped with a
    warning; without, records more than a sane gap away from the file's other frames are
    (:mod:`broadtrack_graph.track.detection_frames`).
    """
    if detections.image_size is None:
        raise InputError(None, "detections file states no image size")
    width, height = detections.image_size
    if source is not None:
        bound_to_window(detections, source.start, source.end)
    else:
        bound_by_gap(detections)
        if start is not None or end is not None:
            bound_to_window(detections, start or 0, end if end is not None else detections.last_frame + 1)
        if not detections.frames:
            raise InputError(None, f"no detection record in the frames {start or 0}..{end}; check --start/--end")
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


def mask_file_detections(mask_path: Path, observations: FrameObservations, width_px: int,
                         height_px: int) -> Detections | None:
    """A marking mask named by a detections file, as detections (for confidence and re-initialisation).

    Args:
        mask_path: the mask PNG (:mod:`broadtrack_graph.io.mask_png`), read at (width_px, height_px).
        observations: the frame's observations from the file (their lines and keypoints are kept).

    Returns:
        Detections with the mask, its playing field when the PNG has one, and up to ~2000 of the
        mask's pixels as marking points; None (with a warning) when the PNG cannot be read.
    """
    masks = read_mask_png(mask_path, width_px, height_px)
    if masks is None:
        return None
    mask, field = masks
    ys, xs = np.nonzero(mask)
    keep = slice(None, None, max(1, len(xs) // 2000))
    return Detections(width_px, height_px, lines_px=dict(observations.lines_px),
                      marking_points_px=np.column_stack([xs[keep], ys[keep]]).astype(float),
                      keypoints=observations.keypoints, marking_mask=mask, field_mask=field)
