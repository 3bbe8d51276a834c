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
    repeats: "PendingFrame | None" = None  # the entry of the frame whose image this one repeats (its record is copied)


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
        self._last: PendingFrame | None = None  # the last frame's entry (a repeated frame copies its record)

    def add(self, entry: PendingFrame) -> None:
        """A frame handed to the solver: its record is built when its estimate is released."""
        self._pending.append(entry)
        self._last = entry

    def emit_now(self, frame: FrameInput, status: str, reason: str) -> None:
        """A frame without an estimate: its record is final now (written after the frames before it)."""
        entry = PendingFrame(frame, status, reason)
        entry.record = TrackRecord(frame.frame_index, frame.frame_id, frame.time_s, None, {}, None, False, status, reason)
        self.add(entry)
        self.flush()

    def can_repeat(self) -> bool:
        """Whether there is a previous frame whose record a repeated frame can carry."""
        return self._last is not None

    def repeat(self, frame: FrameInput) -> None:
        """A frame showing the previous frame's image again: its record is that frame's, once that one is final
        (:meth:`~broadtrack_graph.types.track_record.TrackRecord.repeated_at`)."""
        entry = PendingFrame(frame, FrameStatus.TRACKED, repeats=self._last)
        self.add(entry)
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

    @staticmethod
    def _repeated(entry: PendingFrame) -> bool:
        """Whether ``entry`` repeats a frame whose record is final: then it gets its record (the frame repeated comes
        before it in the queue, so it is written by then)."""
        source = entry.repeats
        if source is None or source.record is None:
            return False
        frame = entry.frame
        entry.record = source.record.repeated_at(frame.frame_index, frame.frame_id, frame.time_s)
        return True

    def close_unreleased(self) -> None:
        """The end of the run: frames the solver never released get a failed record; everything is written."""
        for entry in self._pending:
            if entry.record is None and not self._repeated(entry):
                entry.record = TrackRecord(entry.frame.frame_index, entry.frame.frame_id, entry.frame.time_s, None, {},
                                           None, False, FrameStatus.FAILED, "no estimate released")
        self.flush()

    def flush(self) -> None:
        """Write the final records at the head of the queue (frame order)."""
        while self._pending and (self._pending[0].record is not None or self._repeated(self._pending[0])):
            record = self._pending.popleft().record
            started = time.perf_counter()
            self.writer.write(record)  # records are read back from the file (RunResult.records)
            self.timings["write_s"] += time.perf_counter() - started
            if self.on_final is not None:
                self.on_final(record)
