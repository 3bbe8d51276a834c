"""Offline back-fill: frames of a pitch shot without a camera get one, walked in from the nearest frame that has one.

In the offline modes a shot's frames before its first lock (nothing found yet, or a chain not
confident yet) and after the track is lost need not stay empty: the frame next to them has a
camera. A frame that ends without a camera keeps its markings as the weight-free detector
found them (:class:`~broadtrack_graph.detect.found_markings.FoundMarkings`, masks bit-packed: about
0.2 MB at the working size). When the next frame with a camera is final, the gap is walked
backwards from it: each frame's points are named with the camera of its neighbour, the camera
is refined on them (:func:`~broadtrack_graph.graph.single_frame.refine_single_frame`, that camera's
tripod held) and kept when the tracker's confidence (the marking map against the projected
template) reaches the threshold; the walk stops at the first frame that does not. A gap still
open at a cut or at the end is walked forwards from the camera before it. Gaps longer than
``max_frames`` are left alone (their markings are dropped as soon as the gap grows beyond it),
so memory stays bounded over a match. No I/O.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from broadtrack_graph.detect.detector import Detections, PredictedCamera
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves, TemplateSampling
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.builder import GraphBuilder
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.single_frame import refine_single_frame
from broadtrack_graph.types.observations import FrameObservations
from broadtrack_graph.types.status import FrameStatus

WALKABLE_STATUSES = (FrameStatus.FAILED, FrameStatus.NO_PITCH, FrameStatus.UNPLACED, FrameStatus.MISSING_FRAME)
"""Statuses of frames a gap is made of (a missing frame has nothing to name: it stops a walk)."""

NAMING_UNCERTAINTY_PX = 3.0
"""How far (pixels, 1 sigma) a neighbour's camera is taken to be off when it names a frame's points."""


@dataclass(frozen=True)
class PackedMarkings:
    """A frame's markings found ahead (what naming needs), its masks bit-packed.

    points_work_px: (N, 2) centre-line points at the working size; scale: working / frame pixels;
    work_size: (w, h); width_px, height_px: the frame's size; masks: name -> (packed bits, (h, w)).
    """

    points_work_px: np.ndarray
    scale: float
    work_size: tuple[int, int]
    width_px: int
    height_px: int
    marking_points_px: np.ndarray
    masks: dict

    @classmethod
    def pack(cls, found) -> "PackedMarkings":
        """From a :class:`~broadtrack_graph.detect.found_markings.FoundMarkings`."""
        d = found.unnamed
        masks = {name: (np.packbits(m.astype(bool)), m.shape) for name, m in
                 (("marking_mask", d.marking_mask), ("field_mask", d.field_mask), ("player_mask", d.player_mask))
                 if m is not None}
        return cls(np.asarray(found.points_work_px, float), float(found.scale), tuple(found.work_size), d.width_px,
                   d.height_px, np.asarray(d.marking_points_px, float), masks)

    def found(self):
        """Back to a FoundMarkings the detector can name."""
        from broadtrack_graph.detect.found_markings import FoundMarkings

        masks = {name: np.unpackbits(bits, count=int(np.prod(shape))).reshape(shape).astype(bool)
                 for name, (bits, shape) in self.masks.items()}
        unnamed = Detections(self.width_px, self.height_px, marking_points_px=self.marking_points_px, **masks)
        return FoundMarkings(unnamed, self.points_work_px, self.work_size, self.scale, 0.0)


@dataclass(frozen=True)
class Backfilled:
    """A frame given a camera by the back-fill: the camera, its confidence, the frame it was walked from,
    the camera id of that frame, and the named observations it was refined on."""

    camera: Camera
    confidence: float
    source: int
    camera_id: str | None
    observations: FrameObservations


Namer = Callable[[object, PredictedCamera], Detections]
"""``(found markings, predicted camera) -> Detections``: the detector's naming (``WeightFreeDetector.name``)."""
Confidence = Callable[..., float | None]
"""``(camera, observations, detections, curves, sampling) -> confidence``: the tracker's confidence."""


class Backfill:
    """Collects the camera-less frames of the current gap and walks them in (module docstring).

    Args:
        name: the detector's naming (:data:`Namer`).
        confidence: the tracker's confidence (:data:`Confidence`).
        pitch, curves, sampling: the template.
        graph_config: sigmas of the single-frame refinement.
        threshold: a walked camera must be at least this confident.
        max_frames: longer gaps are not walked.
        tripod_of: camera id -> its tripod (None: the focal point moves freely).
    """

    def __init__(self, name: Namer, confidence: Confidence, pitch: PitchTemplate, curves: TemplateCurves,
                 sampling: TemplateSampling, graph_config: GraphConfig, threshold: float, max_frames: int,
                 tripod_of: Callable[[str | None], Tripod | None]) -> None:
        self.name, self.confidence = name, confidence
        self.pitch, self.curves, self.sampling = pitch, curves, sampling
        self.graph_config, self.threshold, self.max_frames = graph_config, threshold, max_frames
        self.tripod_of = tripod_of
        self.recovered: dict[int, Backfilled] = {}
        self._gap: list[tuple[int, PackedMarkings | None]] = []
        self._too_long = False
        self._last: tuple[int, Camera, str | None] | None = None  # the last frame with a camera in this shot
        self._builder: GraphBuilder | None = None
        self._ahead: dict[int, tuple[object | None, bool]] = {}  # frame -> (markings found ahead, a cut before it)
        self.seconds = 0.0

    def note(self, frame) -> None:
        """A frame entering the loop (a :class:`~broadtrack_graph.track.inputs.FrameInput`): keep what it found
        ahead until its record is final (a few frames; the lag of the smoother)."""
        cut = frame.shot is not None and (frame.shot.cut or frame.shot.is_other_view)
        markings = frame.markings
        if getattr(markings, "faint", None) is not None:
            markings = replace(markings, faint=None)  # its faint look's colour image is not needed here
        self._ahead[frame.frame_index] = (markings, cut)

    def final(self, record) -> None:
        """A record became final (a :class:`~broadtrack_graph.types.track_record.TrackRecord`, frame order)."""
        started = time.perf_counter()
        found, cut = self._ahead.pop(record.frame_index, (None, False))
        if cut:
            self._cut()
        if record.camera is not None:
            self.with_camera(record.frame_index, record.camera, record.camera_id)
        elif record.status in WALKABLE_STATUSES:
            self.without_camera(record.frame_index, found)
        else:
            self._cut()  # another view: nothing is walked across it
        self.seconds += time.perf_counter() - started

    def finish(self) -> None:
        """The end of the run: an open gap is walked forwards from the camera before it."""
        started = time.perf_counter()
        self._cut()
        self.seconds += time.perf_counter() - started

    def without_camera(self, frame_index: int, found) -> None:
        """A final frame without a camera (found: its FoundMarkings, or None: nothing to name)."""
        if self._too_long:
            return
        self._gap.append((frame_index, None if found is None else PackedMarkings.pack(found)))
        if len(self._gap) > self.max_frames:
            self._gap, self._too_long = [], True

    def with_camera(self, frame_index: int, camera: Camera, camera_id: str | None) -> None:
        """A final frame with a camera: the open gap is walked backwards from it (forwards from the one before)."""
        if self._gap and not self._too_long:
            self._walk(list(reversed(self._gap)), frame_index, camera, camera_id)
            if self._last is not None:
                self._walk(self._gap, *self._last)
        self._gap, self._too_long = [], False
        self._last = (frame_index, camera, camera_id)

    def _cut(self) -> None:
        """The shot ends: an open gap is walked forwards from the camera before it; nothing crosses the cut."""
        if self._gap and not self._too_long and self._last is not None:
            self._walk(self._gap, *self._last)
        self._gap, self._too_long, self._last = [], False, None

    def _walk(self, frames: list[tuple[int, PackedMarkings | None]], source: int, camera: Camera,
              camera_id: str | None) -> None:
        tripod = self.tripod_of(camera_id)
        for frame_index, packed in frames:
            if packed is None:
                break
            detections = self.name(packed.found(), PredictedCamera(camera, NAMING_UNCERTAINTY_PX))
            observations = detections.to_observations(frame_index, None, with_marking_mask=False)
            if not observations.lines_px:
                break
            if self._builder is None:
                self._builder = GraphBuilder(observations.width_px, observations.height_px, self.pitch,
                                             self.graph_config)
            refined, _ = refine_single_frame(camera, observations, self.pitch, tripod, self.graph_config,
                                             self._builder)
            if refined is None:
                break
            confidence = self.confidence(refined, observations, detections, self.curves, self.sampling)
            if confidence is None or confidence < self.threshold:
                break
            previous = self.recovered.get(frame_index)
            if previous is None or confidence > previous.confidence:
                self.recovered[frame_index] = Backfilled(refined, float(confidence), source, camera_id, observations)
            camera = refined
