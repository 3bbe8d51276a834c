"""The frames of a run waiting for their estimates, and their records written in frame order.

A frame's record is final when its estimate is released (at once online, ``lag`` frames later
with the fixed-lag smoother) or when it gets none (a missing frame, another view, nothing found).
Final records are written from the head of the queue, in frame order: camera file, then a
flushed ``track.jsonl`` line, so an interrupted run keeps every frame it finished.
"""

from __future__ import annotations

import time
from collections import deque
from dataclasses import dataclass
from typing import Callable

import numpy as np

from broadtrack_graph.detect.detector import Detections
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.graph.estimates import FrameEstimate
from broadtrack_graph.io.track_writer import TrackWriter
from broadtrack_graph.track.inputs import FrameInput
from broadtrack_graph.track.result import std_fields
from broadtrack_graph.types.observations import FrameObservations
from broadtrack_graph.types.status import FrameStatus
from broadtrack_graph.types.track_record import TrackRecord


@dataclass
class PendingFrame:
    """A frame waiting for its estimate (fixed-lag) before its record can be written."""

    frame: FrameInput
    status: str
    reason: str | None = None
    reinitialised: bool = False
    detections: Detections | None = None
    observations: FrameObservations | None = None
    record: TrackRecord | None = None
    override_camera: Camera | None = None
    confidence: float | None = None  # of confidence_camera, computed when the frame was added
    suppress_camera: bool = False  # the frame's estimate is not trusted: write no camera
    confidence_camera: Camera | None = None
    camera_id: str | None = None  # the broadcast camera of the frame


class RecordQueue:
    """Pending frames, their records built as estimates are released, written in frame order.

    Args:
        writer: writes each final record.
        rescore: ``(camera, observations, detections) -> confidence`` for a released camera that is not
            the one scored when its frame was added (a smoother's).
        on_final: told of every record once it is written (e.g. the offline back-fill), or None.
        timings: the run's seconds per stage (``write_s`` is added to).
    """

    def __init__(self, writer: TrackWriter, rescore: Callable, on_final: Callable[[TrackRecord], None] | None,
                 timings: dict) -> None:
        self.writer, self.rescore, self.on_final, self.timings = writer, rescore, on_final, timings
        self._pending: deque[PendingFrame] = deque()

    def add(self, entry: PendingFrame) -> None:
        """A frame handed to the solver: its record is built when its estimate is released."""
        self._pending.append(entry)

    def emit_now(self, frame: FrameInput, status: str, reason: str) -> None:
        """A frame without an estimate: its record is final now (written after the frames before it)."""
        entry = PendingFrame(frame, status, reason)
        entry.record = TrackRecord(frame.frame_index, frame.frame_id, frame.time_s, None, {}, None, False, status, reason)
        self._pending.append(entry)
        self.flush()

    def resolve(self, estimate: FrameEstimate) -> None:
        """Build the record of the pending frame this released estimate belongs to."""
        for entry in self._pending:
            if entry.frame.frame_index == estimate.frame_index and entry.record is None:
                camera = None if entry.suppress_camera else (entry.override_camera or estimate.camera)
                status = entry.status if (camera is not None or entry.status == FrameStatus.MOTION_PRIOR) else FrameStatus.FAILED
                reason = entry.reason if (camera is not None or entry.suppress_camera) else (estimate.reason or "solver failed")
                confidence = None
                if camera is not None and entry.confidence_camera is not None and \
                        np.allclose(camera.to_vector(), entry.confidence_camera.to_vector(), rtol=0, atol=1e-9):
                    confidence = entry.confidence  # online: the camera scored when the frame was added
                elif camera is not None:
                    confidence = self.rescore(camera, entry.observations, entry.detections)
                active = tuple(sorted(k for k, v in (estimate.active_factors or {}).items() if v))
                entry.record = TrackRecord(entry.frame.frame_index, entry.frame.frame_id, entry.frame.time_s, camera,
                                           std_fields(estimate) if camera is not None else {}, confidence,
                                           entry.reinitialised, status, reason, active,
                                           entry.camera_id if camera is not None else None)
                entry.detections = None
                return

    def close_unreleased(self) -> None:
        """The end of the run: frames the solver never released get a failed record; everything is written."""
        for entry in self._pending:
            if entry.record is None:
                entry.record = TrackRecord(entry.frame.frame_index, entry.frame.frame_id, entry.frame.time_s, None, {},
                                           None, False, FrameStatus.FAILED, "no estimate released")
        self.flush()

    def flush(self) -> None:
        """Write the final records at the head of the queue (frame order)."""
        while self._pending and self._pending[0].record is not None:
            record = self._pending.popleft().record
            started = time.perf_counter()
            self.writer.write(record)  # records are read back from the file (RunResult.records)
            self.timings["write_s"] += time.perf_counter() - started
            if self.on_final is not None:
                self.on_final(record)
