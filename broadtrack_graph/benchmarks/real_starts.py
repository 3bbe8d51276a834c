"""Shots started mid-clip, for ``bench real --starts STEP``: how soon a camera is found from nothing on real frames.

A broadcast cuts into a camera's shot anywhere: a zoomed box view after a fast pan, a wide view of one touchline, a
centre circle. Each real clip is tracked online again from every ``step``-th frame, ``length`` frames at a time, with
nothing known before the start (:func:`track_starts`); each start reports how many frames passed before its first
written camera, and every camera written is scored by the alignment check that does not use the tracker's detector
(:mod:`broadtrack_graph.metrics.line_alignment`, as :mod:`~broadtrack_graph.benchmarks.real_video` scores a whole
clip). Per clip and pooled (:func:`starts_figures`): the starts, those placed within :data:`FOUND_WITHIN_FRAMES`
frames of their start, the median delay of those placed, the written cameras and the misaligned ones. Starts on frames
known to show another view (a close-up) are not tried.
"""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from broadtrack_graph.actions.track import track_input
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import fitting_curves
from broadtrack_graph.io.run_folder import RunFolder
from broadtrack_graph.metrics.line_alignment import AlignmentConfig, line_alignment, line_pixels
from broadtrack_graph.track.config import TrackingConfig

FOUND_WITHIN_FRAMES = 10
"""A start is placed when a camera is written on one of its first this many frames (its first frame is delay 0)."""


def start_frames(decoded: int, step: int, length: int, other_views=()) -> list[int]:
    """The first frames of the starts tried on a clip of ``decoded`` frames: every ``step``-th frame leaving ``length``
    frames to track (at least the first), none inside a known other view ((start, end exclusive) ranges)."""
    last = max(0, decoded - length)
    return [s for s in range(0, last + 1, step) if not any(a <= s < b for a, b in other_views)]


def track_starts(video: Path, out_dir: Path, starts: list[int], length: int, options: dict,
                 progress: bool = False) -> dict[int, Path]:
    """Track ``video`` online from each start for ``length`` frames, nothing known before it; {start: run folder}."""
    runs = {}
    for start in starts:
        run_dir = Path(out_dir) / f"start-{start:05d}"
        track_input(video, run_dir, TrackingConfig(mode="online", **options), start=start, end=start + length,
                    progress=progress)
        runs[start] = run_dir
    return runs


def score_starts(video: Path, runs: dict[int, Path], config: AlignmentConfig = AlignmentConfig()) -> list[dict]:
    """Per start (in order): {"start", "first_camera_delay" (frames after the start; None: no camera written),
    "cameras", "aligned", "misaligned"} (cameras the check cannot score, no marking seen, are neither). The clip is
    decoded once; each frame scores the cameras every start wrote on it."""
    written: dict[int, list[tuple[int, object]]] = {}  # frame -> [(start, camera)]
    rows = {}
    for start, run_dir in sorted(runs.items()):
        records = [r for r in RunFolder(run_dir).read_track().records if r.camera is not None]
        delays = [r.frame_index - start for r in records]
        rows[start] = {"start": start, "first_camera_delay": min(delays) if delays else None,
                       "cameras": len(records), "aligned": 0, "misaligned": 0}
        for record in records:
            written.setdefault(record.frame_index, []).append((start, record.camera))
    curves = fitting_curves(PitchTemplate())
    capture = cv2.VideoCapture(str(video))
    last = max(written) if written else -1
    index = 0
    while index <= last:
        ok, image = capture.read()
        if not ok:
            break
        if index in written:
            pixels = line_pixels(image, config)
            for start, camera in written[index]:
                alignment = line_alignment(image, camera.rescaled(image.shape[1], image.shape[0]), curves, config,
                                           pixels)
                if alignment is not None:
                    rows[start]["aligned" if alignment.aligned(config) else "misaligned"] += 1
        index += 1
    capture.release()
    return [rows[start] for start in sorted(rows)]


def starts_figures(rows: list[dict], step: int, length: int) -> dict:
    """The figures of a clip's starts (or of several clips' pooled): the module docstring's, with the rows."""
    placed = [r["first_camera_delay"] for r in rows
              if r["first_camera_delay"] is not None and r["first_camera_delay"] < FOUND_WITHIN_FRAMES]
    cameras = sum(r["cameras"] for r in rows)
    misaligned = sum(r["misaligned"] for r in rows)
    return {"step": step, "frames_per_start": length, "starts": len(rows),
            f"placed_within_{FOUND_WITHIN_FRAMES}": len(placed),
            f"placed_within_{FOUND_WITHIN_FRAMES}_share": round(len(placed) / len(rows), 3) if rows else None,
            "median_delay_of_placed": float(np.median(placed)) if placed else None,
            "cameras": cameras, "misaligned": misaligned,
            "misaligned_share": round(misaligned / cameras, 4) if cameras else None,
            "not_placed": [r["start"] for r in rows if r["first_camera_delay"] is None
                           or r["first_camera_delay"] >= FOUND_WITHIN_FRAMES],
            "rows": rows}
