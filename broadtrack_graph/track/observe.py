"""A frame's observations for the solver: its markings named with the predicted camera, and optical flow.

The detector names the markings with the predicted camera (the markings found ahead, in the
thread that decodes the frames, when the detector offers it); the static graphics mask is taken
out; optical flow links the frame to the previous one while the previous camera is trusted
(:func:`~broadtrack_graph.detect.flow.grid_flow`: back-projected through that camera, kept only on
the field and off the players; tracked ahead where the frames are decoded when the markings are found
there, :func:`~broadtrack_graph.detect.flow.flow_candidates`, and only checked against the previous
camera here). A frame's markings can take their faint look (the faint straight paint added,
:mod:`~broadtrack_graph.detect.faint_lines`): looked at for the court model's second look at a lost frame, kept when
its camera was found on them and for the frames of a chain that needs them. A detections file's frames bring their
observations; flow is added when their images come too. No I/O beyond a detections file's mask images.
"""

from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

from broadtrack_graph.detect.detector import Detections, PredictedCamera
from broadtrack_graph.detect.flow import flow_keep_mask, grid_flow, on_pitch, prepare
from broadtrack_graph.detect.graphics import mask_graphics
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.inputs import FrameInput, mask_file_detections
from broadtrack_graph.types.observations import FrameObservations

RENAMING_UNCERTAINTY_PX = 3.0
"""How far (pixels, 1 sigma) a re-initialised camera is taken to be off when it names its frame's markings."""


class FrameObserver:
    """Turns frames into (observations, detections), keeping the previous frame for flow.

    Args:
        detector: a FieldDetector for image input (None when every frame brings observations).
        config: tracking options (flow settings, ``use_flow``).
        width_px, height_px: the run's resolution (observations are rescaled to it).
        pitch: the template (flow keeps points within its bounds).
        mask_paths: frame index -> marking-mask PNG named by a detections file.
        timings: the run's seconds per stage (``detect_s``, ``flow_s``, ``markings_ahead_s`` are added to).
    """

    def __init__(self, detector, config: TrackingConfig, width_px: int, height_px: int, pitch: PitchTemplate,
                 mask_paths: dict, timings: dict) -> None:
        self.detector, self.config, self.W, self.H = detector, config, width_px, height_px
        self.half_pitch_m = (pitch.dimensions.length_m / 2, pitch.dimensions.width_m / 2)
        self.mask_paths, self.timings = mask_paths, timings
        self._prev_grey: np.ndarray | None = None
        self._prev_keep_mask: np.ndarray | None = None
        self._looked = None  # (frame, its markings' faint look): the last frame looked at (faint_look)

    def unlink(self) -> None:
        """The next frame is not linked to the previous one by flow."""
        self._prev_grey = None

    def detect(self, frame: FrameInput, predicted: PredictedCamera | None, faint_look: bool = False) -> Detections:
        """The frame's detections without what lies under graphics; from the markings found ahead when there, with
        their faint look when asked (:meth:`take_faint_look`). A frame whose markings were not found ahead (one the
        shot step reads as another view) has them found here and kept on it, as ahead."""
        if frame.markings is None and frame.image is not None and hasattr(self.detector, "find_markings"):
            frame.markings = self.detector.find_markings(frame.image)
        if faint_look:
            self.take_faint_look(frame)
        if frame.markings is not None:
            detections = self.detector.name(frame.markings, predicted)
        else:
            detections = self.detector.detect(frame.image, predicted)
        return mask_graphics(detections, frame.graphics_mask)

    def faint_look(self, frame: FrameInput) -> Detections | None:
        """The frame's unnamed detections with their faint look (the faint straight paint added to the markings found
        ahead: the detector's ``with_faint_lines``), without what lies under graphics; None when the markings offer
        none or it adds nothing. Looked for once a frame; the frame's markings stay as found
        (:meth:`take_faint_look`)."""
        if frame.markings is None or frame.markings.faint is None:
            return None
        if self._looked is None or self._looked[0] is not frame:
            self._looked = (frame, self.detector.with_faint_lines(frame.markings))
        looked = self._looked[1]
        return mask_graphics(looked.unnamed, frame.graphics_mask) if looked.faint_points_added else None

    def take_faint_look(self, frame: FrameInput) -> None:
        """The frame's markings are their faint look's from here on (:meth:`faint_look`); nothing when the markings
        offer none."""
        if frame.markings is not None and frame.markings.faint is not None:
            self.faint_look(frame)
            frame.markings, self._looked = self._looked[1], None

    def without_faint_look(self, frame: FrameInput) -> Detections | None:
        """The frame's unnamed detections as they were before its faint look added anything (None: it added nothing,
        or was not taken)."""
        if not getattr(frame.markings, "faint_points_added", 0):
            return None
        return mask_graphics(frame.markings.faint_look_of.unnamed, frame.graphics_mask)

    def observe(self, frame: FrameInput, predicted: PredictedCamera | None, previous: Camera | None,
                faint_look: bool = False) -> tuple[FrameObservations, Detections | None]:
        """(observations at the run's resolution, detections or None) of one frame.

        Args:
            predicted: the camera the markings are named with (None: lost, nothing is named).
            previous: the previous frame's trusted camera (None: no flow).
            faint_look: the markings with their faint look (:meth:`take_faint_look`).

        Raises:
            ValueError: the detector refused the image.
        """
        detections, grey, observations = None, None, frame.observations
        if frame.has_image:
            if observations is None:
                found_ahead = frame.markings is not None  # else found here, within detect_s
                started = time.perf_counter()
                detections = self.detect(frame, predicted, faint_look)
                self.timings["detect_s"] += time.perf_counter() - started
                if found_ahead:
                    self.timings["markings_ahead_s"] += frame.markings.seconds
            started = time.perf_counter()
            if self.config.use_flow:
                grey = frame.flow_frame if frame.flow_frame is not None else prepare(frame.image, self.config.flow)
            self.timings["flow_s"] += time.perf_counter() - started
        if detections is None and frame.frame_index in self.mask_paths and observations is not None:
            detections = mask_file_detections(self.mask_paths[frame.frame_index], observations, self.W, self.H)
        flow = None
        if grey is not None and self._prev_grey is not None and previous is not None:
            started = time.perf_counter()
            if self._flow_ahead_applies(frame.flow_ahead):
                flow = on_pitch(frame.flow_ahead, previous, self.config.flow, self.half_pitch_m)
            else:
                flow = grid_flow(self._prev_grey, grey, self.W, self.H, previous, self._prev_keep_mask,
                                 self.config.flow, self.half_pitch_m)
            self.timings["flow_s"] += time.perf_counter() - started
        if detections is not None and frame.observations is None:
            observations = detections.to_observations(frame.frame_index, flow, with_marking_mask=False)
            self._prev_keep_mask = flow_keep_mask(detections)
        elif flow is not None:
            observations = replace(observations, flow=flow)
        self._prev_grey = grey
        if observations.width_px != self.W or observations.height_px != self.H:
            observations = observations.rescaled(self.W, self.H)
        return observations, detections

    def _flow_ahead_applies(self, ahead) -> bool:
        """The flow found ahead starts from this loop's previous frame's image, with its keep mask, at the run's size.
        The image is compared by value: a process of its own sends each frame's copy apart, so the flow's copy of the
        previous image is never the very object the loop holds (a thread's is)."""
        if ahead is None or self._prev_grey is None or (ahead.width_px, ahead.height_px) != (self.W, self.H):
            return False
        if not _equal_maps(ahead.prev_frame.grey, self._prev_grey.grey):
            return False
        if ahead.keep_mask is None or self._prev_keep_mask is None:
            return ahead.keep_mask is None and self._prev_keep_mask is None
        return _equal_maps(ahead.keep_mask, self._prev_keep_mask)

    def named_by(self, frame: FrameInput, observations: FrameObservations, detections: Detections | None,
                 camera: Camera) -> tuple[FrameObservations, Detections | None]:
        """A re-initialised frame's observations without flow, its unnamed markings named with its new camera
        (so the first frame of a chain has line factors)."""
        observations = replace(observations, flow=None)
        if (self.detector is not None and frame.has_image and detections is not None
                and detections.marking_mask is not None and not observations.lines_px):
            detections = self.detect(frame, PredictedCamera(camera, RENAMING_UNCERTAINTY_PX))
            observations = detections.to_observations(frame.frame_index, None, with_marking_mask=False)
        return observations, detections

    def shows_no_pitch(self, observations: FrameObservations, detections: Detections | None) -> bool:
        """Too little to fit: too little grass or too few marking points (``min_grass_share``, ``min_marking_points``)."""
        if detections is not None:
            grass = detections.field_mask.mean() if detections.field_mask is not None else 1.0
            points = len(detections.marking_points_px) + sum(len(p) for p in detections.lines_px.values())
            return grass < self.config.min_grass_share or points < self.config.min_marking_points
        return observations.is_empty or (observations.line_point_count < 4 and not observations.keypoints)


def _equal_maps(a: np.ndarray, b: np.ndarray) -> bool:
    """Whether two images or masks are the same (the same object, or equal in shape and every value)."""
    return a is b or (a.shape == b.shape and np.array_equal(a, b))
