"""Writing a run folder frame by frame: camera files, flushed ``track.jsonl`` lines, ``summary.json``.

The folder's layout is :class:`~broadtrack_graph.io.run_folder.RunFolder`'s; each line is a
:class:`~broadtrack_graph.types.track_record.TrackRecord`.
"""

from __future__ import annotations

import collections
import json
import logging
import math
import time
from datetime import datetime, timezone
from pathlib import Path
from typing import Callable

from broadtrack_graph.io.process_prefetch import cpu_seconds
from broadtrack_graph.io.run_folder import CAMERA_DIR, CAMERA_DIR_960, TRACK_FILE, RunFolder
from broadtrack_graph.io.track_record import record_to_json
from broadtrack_graph.types.status import FrameStatus
from broadtrack_graph.types.track_record import TrackRecord

logger = logging.getLogger(__name__)

RecordWritten = Callable[[TrackRecord, dict], None]
"""Observer of a written record: (the record as written, camera at the writer's resolution; its ``track.jsonl``
object). Called after the line is flushed, so whatever it writes follows the frame's line."""


class TrackWriter:
    """Writes a run folder frame by frame (layout: :mod:`broadtrack_graph.io.run_folder`).

    Args:
        out_dir: run folder (created). Files of an earlier run in it (track.jsonl,
            summary.json, camera_*.json in its camera folders) are replaced.
        width_px, height_px: input resolution; records' cameras must be at it.
        also_960x540: also write cameras_960x540/ (the calibration benchmark's resolution).
        run_info: plain data stored in summary.json under "run" (input, mode, options).
        summary_every: rewrite summary.json every this many frames.
        on_write: observer of every written record (:data:`RecordWritten`), or None; may be set later
            (``writer.on_write = ...``) before the first record.

    Use as a context manager, or call :meth:`close` at the end; a run that is not
    closed leaves ``"complete": false`` in its last summary.
    """

    def __init__(
        self,
        out_dir: str | Path,
        width_px: int,
        height_px: int,
        also_960x540: bool = False,
        run_info: dict | None = None,
        summary_every: int = 100,
        on_write: RecordWritten | None = None,
    ) -> None:
        if width_px <= 0 or height_px <= 0:
            raise ValueError(f"image size must be positive, got {width_px}x{height_px}")
        self.folder = RunFolder(out_dir)
        self.out_dir = self.folder.path
        self.width_px, self.height_px = int(width_px), int(height_px)
        self.also_960x540 = also_960x540
        self.run_info = dict(run_info or {})
        self.summary_every = max(1, int(summary_every))
        self.on_write = on_write
        self.folder.create(also_960x540)
        removed = self.folder.remove_camera_files()
        if removed:
            logger.info("%s: removed %d camera files of an earlier run", self.out_dir, removed)
        self._track = open(self.folder.track_path, "w", encoding="utf-8")
        self._started_wall = time.time()
        self._started_cpu = cpu_seconds()  # the process's CPU time (every thread, ended children) at the start
        self._started_utc = datetime.now(timezone.utc).isoformat(timespec="seconds")
        self._status_counts = {status.value: 0 for status in FrameStatus}
        self._frames = 0
        self._reinitialisations = 0
        self._confidence_sum = 0.0
        self._confidence_count = 0
        self._last_frame_index: int | None = None
        self._recent_write_times: collections.deque = collections.deque(maxlen=26)
        self._last_record: TrackRecord | None = None
        self.closed = False
        self._write_summary(complete=False)

    # ----------------------------------------------------------------- per frame

    def write(self, record: TrackRecord) -> None:
        """Write one finished frame: its camera file(s), then its track line (flushed), then tell the observer."""
        if self.closed:
            raise RuntimeError("TrackWriter is closed")
        camera_file = None
        if record.camera is not None:
            camera = record.camera
            camera = camera.rescaled(self.width_px, self.height_px)
            camera_file = self.folder.write_camera(record.frame_id, camera, self.also_960x540, record.camera_id)
            record = TrackRecord(**{**record.__dict__, "camera": camera})
        line = record_to_json(record, camera_file)
        self._track.write(json.dumps(line, allow_nan=False) + "\n")
        self._track.flush()
        self._frames += 1
        self._status_counts[record.status] += 1
        self._reinitialisations += int(record.reinitialised)
        if record.confidence is not None and math.isfinite(record.confidence):
            self._confidence_sum += record.confidence
            self._confidence_count += 1
        self._last_frame_index = record.frame_index
        self._last_record = record
        self._recent_write_times.append(time.perf_counter())
        if self._frames % self.summary_every == 0:
            self._write_summary(complete=False)
        if self.on_write is not None:
            self.on_write(record, line)

    def progress_postfix(self) -> dict[str, str]:
        """Fields for a tqdm bar (``bar.set_postfix(writer.progress_postfix(), refresh=False)``):
        current fps over the last 25 frames, the last frame's confidence and status."""
        times = self._recent_write_times
        fps = (len(times) - 1) / (times[-1] - times[0]) if len(times) > 1 and times[-1] > times[0] else None
        record = self._last_record
        return {
            "fps": "-" if fps is None else f"{fps:.1f}",
            "conf": "-" if record is None or record.confidence is None else f"{record.confidence:.2f}",
            "status": "-" if record is None else record.status,
        }

    # ----------------------------------------------------------------- summary

    def summary(self, complete: bool, extra: dict | None = None) -> dict:
        """The summary.json object for the frames written so far."""
        elapsed = time.time() - self._started_wall
        cpu = cpu_seconds() - self._started_cpu
        with_camera = sum(self._status_counts[s] for s in FrameStatus if s.has_camera)
        return {
            "complete": bool(complete),
            "interrupted": False,  # True (set by interrupt()) when Ctrl-C or SIGTERM stopped the run
            "started_utc": self._started_utc,
            "updated_utc": datetime.now(timezone.utc).isoformat(timespec="seconds"),
            "width_px": self.width_px,
            "height_px": self.height_px,
            "frames_written": self._frames,
            "frames_with_camera": with_camera,
            "completeness": with_camera / self._frames if self._frames else None,
            "status_counts": dict(self._status_counts),
            "reinitialisations": self._reinitialisations,
            "mean_confidence": self._confidence_sum / self._confidence_count if self._confidence_count else None,
            "last_frame_index": self._last_frame_index,
            "elapsed_s": round(elapsed, 3),
            "fps": round(self._frames / elapsed, 3) if elapsed > 0 else None,
            # The process's CPU seconds since the run began, every thread (tracking, decoding, OpenCV's, the video
            # decoder's): per frame, what the run costs a machine; over the wall time, the cores it kept busy.
            "cpu_s": round(cpu, 3),
            "cpu_ms_per_frame": round(1000.0 * cpu / self._frames, 2) if self._frames else None,
            "cores_used": round(cpu / elapsed, 2) if elapsed > 0 else None,
            "files": {"track": TRACK_FILE, "cameras": CAMERA_DIR, "cameras_960x540": CAMERA_DIR_960 if self.also_960x540 else None},
            "run": self.run_info,
            **(extra or {}),
        }

    def _write_summary(self, complete: bool, extra: dict | None = None) -> dict:
        summary = self.summary(complete, extra)
        self.folder.write_summary(summary)
        return summary

    def close(self, extra_summary: dict | None = None) -> dict:
        """Close track.jsonl and write the final summary (``"complete": true``); returns it."""
        if self.closed:
            return self.folder.read_summary()
        self._track.close()
        self.closed = True
        return self._write_summary(complete=True, extra=extra_summary)

    def interrupt(self, reason: str = "interrupted") -> dict:
        """Stop after Ctrl-C / SIGTERM: close track.jsonl and rewrite summary.json with ``"interrupted": true``
        and the counts of the frames actually written (files written so far are kept); returns the summary."""
        if self.closed:
            return self.folder.read_summary()
        self._track.close()
        self.closed = True
        return self._write_summary(complete=False, extra={"interrupted": True, "error": reason})

    def __enter__(self) -> "TrackWriter":
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            self.close()
        elif issubclass(exc_type, KeyboardInterrupt):
            self.interrupt()
        else:
            # Keep what was written; the summary says the run did not finish.
            self._track.close()
            self.closed = True
            self._write_summary(complete=False, extra={"error": f"{exc_type.__name__}: {exc}"[:300]})
