"""Offline recovery of the frames a forward pass left without a camera.

The offline modes (fixed-lag, batch) see the whole clip, so a frame that could not be
re-initialised forward (the opening frames before the first lock, a short gap) can be
reached from its nearest frame with a camera: walk into the gap from each side, one frame
at a time, refining the neighbour's camera on the frame's own observations (keypoints, named
lines; no flow) with the single-frame robust refinement, and keep a camera while its
confidence stays at the tracking threshold. Backwards from the first good frame recovers
the opening; a gap between two good frames is walked from both ends. The recovered frames
are then smoothed with their neighbours (see :mod:`broadtrack_graph.track.passes`).

Only frames whose status says the forward pass failed on them (failed, no-pitch,
no-detections: not missing frames, nor frames of another view) and whose observations are
known are recovered. No I/O.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field, replace

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateSampling, fitting_curves
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.builder import GraphBuilder
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.single_frame import refine_single_frame
from broadtrack_graph.reinit.frame import frame_confidence
from broadtrack_graph.types.observations import FrameObservations
from broadtrack_graph.types.status import FrameStatus
from broadtrack_graph.types.track_record import TrackRecord

log = logging.getLogger(__name__)

RECOVERABLE_STATUSES = (FrameStatus.FAILED, FrameStatus.NO_PITCH, FrameStatus.NO_DETECTIONS, FrameStatus.UNPLACED)
"""Statuses of frames the recovery may give a camera (the forward pass failed on them)."""


@dataclass(frozen=True)
class _Walked:
    """A gap frame's camera from a walk: the camera, its confidence and the frame index the walk started from."""

    camera: Camera
    confidence: float
    source_frame: int


@dataclass
class Recovery:
    """What a recovery did.

    records: the run's records, recovered frames replaced (same order and length).
    recovered: frame indices that got a camera.
    gaps: [first, last] frame index of every gap tried.
    unrecovered: frame indices of those gaps still without a camera.
    """

    records: list[TrackRecord]
    recovered: list[int] = field(default_factory=list)
    gaps: list[list[int]] = field(default_factory=list)
    unrecovered: list[int] = field(default_factory=list)

    def info(self) -> dict:
        return {"recovered_frames": len(self.recovered), "gaps": self.gaps, "unrecovered_frames": len(self.unrecovered)}


def recoverable_gaps(records: list[TrackRecord], observations: dict[int, FrameObservations],
                     max_frames: int) -> list[tuple[int, int]]:
    """Runs of records (positions [lo, hi)) that may be recovered: without a camera, a recoverable
    status and known observations, next to a record with a camera of the adjacent frame, and at
    most max_frames long."""
    def candidate(r: TrackRecord) -> bool:
        return r.camera is None and r.status in RECOVERABLE_STATUSES and r.frame_index in observations

    gaps = []
    i = 0
    while i < len(records):
        if not candidate(records[i]):
            i += 1
            continue
        lo = i
        while i < len(records) and candidate(records[i]) and (
                i == lo or records[i].frame_index == records[i - 1].frame_index + 1):
            i += 1
        hi = i
        left = lo > 0 and records[lo - 1].camera is not None and records[lo - 1].frame_index == records[lo].frame_index - 1
        right = hi < len(records) and records[hi].camera is not None and \
            records[hi].frame_index == records[hi - 1].frame_index + 1
        if (left or right) and hi - lo <= max_frames:
            gaps.append((lo, hi))
    return gaps


def recover_gaps(records: list[TrackRecord], observations: dict[int, FrameObservations], pitch: PitchTemplate,
                 graph_config: GraphConfig, confidence_threshold: float, max_frames: int,
                 tripod: Tripod | None = None, tripods: dict[str, Tripod] | None = None) -> Recovery:
    """Give cameras to the frames of recoverable gaps by walking in from their neighbours.

    Args:
        records: every frame's record of a forward pass, in frame order.
        observations: frame index -> the frame's observations (pixels at the records' resolution).
        pitch: the pitch template.
        graph_config: sigmas of the single-frame refinement.
        confidence_threshold: a recovered camera must reach this confidence
            (:func:`~broadtrack_graph.reinit.frame.frame_confidence`); the walk stops at the first
            frame that does not.
        max_frames: longer gaps are left alone.
        tripod: when known, the refinement ties the focal point to it.
        tripods: tripods by camera id (a broadcast's cameras): a walk uses the tripod of the camera it starts
            from, and the recovered frames take that camera's id.
    """
    records = list(records)
    result = Recovery(records)
    gaps = recoverable_gaps(records, observations, max_frames)
    if not gaps:
        return result
    curves = fitting_curves(pitch)
    sampling = TemplateSampling(pitch)
    builder = None
    for lo, hi in gaps:
        result.gaps.append([records[lo].frame_index, records[hi - 1].frame_index])
        found: dict[int, _Walked] = {}
        def tripod_of(record: TrackRecord) -> Tripod | None:
            return (tripods.get(record.camera_id) if record.camera_id is not None else None) if tripods else tripod

        if lo > 0 and records[lo - 1].camera is not None:
            builder = _walk(records, observations, range(lo, hi), records[lo - 1], pitch, graph_config,
                            confidence_threshold, tripod_of(records[lo - 1]), curves, sampling, builder, found)
        if hi < len(records) and records[hi].camera is not None:
            builder = _walk(records, observations, range(hi - 1, lo - 1, -1), records[hi], pitch, graph_config,
                            confidence_threshold, tripod_of(records[hi]), curves, sampling, builder, found)
        for position in range(lo, hi):
            record = records[position]
            if position not in found:
                result.unrecovered.append(record.frame_index)
                continue
            walked = found[position]
            camera, confidence, source = walked.camera, walked.confidence, walked.source_frame
            source_id = next(r.camera_id for r in records if r.frame_index == source)
            records[position] = replace(record, camera=camera, confidence=confidence, status=FrameStatus.TRACKED,
                                        camera_id=source_id,
                                        reinitialised=False, std={},
                                        reason=f"recovered offline from frame {source}",
                                        active_factors=_active(observations[record.frame_index]))
            result.recovered.append(record.frame_index)
    log.info("offline recovery: %d frames recovered in %d gaps, %d left", len(result.recovered), len(gaps),
             len(result.unrecovered))
    return result


def _walk(records, observations, positions, start: TrackRecord, pitch, graph_config, threshold, tripod, curves,
          sampling, builder, found: dict) -> GraphBuilder | None:
    """Refine frame after frame from start's camera along positions; keep the better of two walks per frame."""
    camera = start.camera
    for position in positions:
        obs = observations[records[position].frame_index]
        if builder is None:
            builder = GraphBuilder(obs.width_px, obs.height_px, pitch, graph_config)
        refined, _ = refine_single_frame(camera, obs, pitch, tripod, graph_config, builder)
        if refined is None:
            break
        confidence = frame_confidence(refined, obs, None, curves, sampling)
        if confidence is None or confidence < threshold:
            break
        if position not in found or confidence > found[position].confidence:
            found[position] = _Walked(refined, float(confidence), start.frame_index)
        camera = refined
    return builder


def _active(observations: FrameObservations) -> tuple[str, ...]:
    kinds = []
    if observations.lines_px:
        kinds.append("lines")
    if observations.keypoints is not None and len(observations.keypoints):
        kinds.append("keypoints")
    return tuple(kinds)
