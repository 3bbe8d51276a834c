"""The real part of ``bench broadcast``: real broadcast videos spliced into one video with hard cuts, tracked online.

The splice (:func:`splice_plan`, :func:`write_splice`): the videos of ``--video-dir`` in name
order, one segment of each in turn (lengths cycling through :data:`SEGMENT_LENGTHS` scaled to
``--segment-frames``), then again from the first video, each video continuing where its
previous segment stopped (a camera returning after a cut), until ``--segments`` segments;
every frame resized to one size (default 1280x720); a 50 fps video keeps every second
frame so that all play at about 25 fps. The splice is written under the bench's work folder,
never in the repository (the videos are copyrighted).

Scores: fps (frames / wall seconds of the tracking call), the re-initialisation time share
(summary ``timings_s.reinit_s`` / wall), statuses, the cuts found against the splice's cuts
(:func:`~broadtrack_graph.metrics.broadcast.cut_scores`), and per segment: frames with a
camera, the share of them aligned by the independent line alignment check of
:mod:`broadtrack_graph.metrics.line_alignment` (the one ``bench real`` uses), and the camera
ids seen (:func:`~broadtrack_graph.io.run_folder.read_frame_camera_ids`).
"""

from __future__ import annotations

import time
from collections import Counter
from dataclasses import dataclass
from pathlib import Path

import cv2

from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import fitting_curves
from broadtrack_graph.io.run_folder import RunFolder, read_frame_camera_ids
from broadtrack_graph.io.shots_file import SHOTS_FILE, read_shots
from broadtrack_graph.io.video import open_video_writer
from broadtrack_graph.metrics.broadcast import cut_scores
from broadtrack_graph.metrics.line_alignment import AlignmentConfig, line_alignment, line_pixels
from broadtrack_graph.types.shot import Shot

SEGMENT_LENGTHS = (1.0, 1.17, 0.83, 1.25, 1.08)
"""Relative segment lengths, cycled (120 frames -> 120, 140, 100, 150, 130)."""
TARGET_FPS = 25.0


@dataclass(frozen=True)
class Segment:
    """One segment of the splice.

    video: the source; source_start: its first source frame (0-based, in source frames);
    step: source frames per spliced frame; start, end: spliced frame indices (end exclusive).
    """

    video: Path
    source_start: int
    step: int
    start: int
    end: int

    @property
    def frames(self) -> int:
        return self.end - self.start


def _video_info(path: Path) -> tuple[int, int]:
    """(frame count the container states, step to ~25 fps)."""
    capture = cv2.VideoCapture(str(path))
    if not capture.isOpened():
        raise InputError(path, "cannot open the video")
    count = int(capture.get(cv2.CAP_PROP_FRAME_COUNT) or 0)
    fps = float(capture.get(cv2.CAP_PROP_FPS) or TARGET_FPS)
    capture.release()
    return count, max(1, int(round(fps / TARGET_FPS)))


def splice_plan(videos: list[Path], segment_frames: int = 120, segments: int = 6,
                min_segment_frames: int | None = None) -> list[Segment]:
    """The splice's segments (module docstring), from the stated frame counts of ``videos``.

    A video with fewer than ``min_segment_frames`` frames left (default a quarter of ``segment_frames``, at
    least 2) gives no further segment.
    """
    if not videos:
        raise InputError(None, "no video to splice")
    info = {v: _video_info(v) for v in videos}
    least = max(2, segment_frames // 4) if min_segment_frames is None else int(min_segment_frames)
    used = {v: 0 for v in videos}  # source frames used so far
    plan: list[Segment] = []
    start, turn, idle = 0, 0, 0
    while len(plan) < segments and idle < len(videos):
        video = videos[turn % len(videos)]
        count, step = info[video]
        wanted = int(round(segment_frames * SEGMENT_LENGTHS[len(plan) % len(SEGMENT_LENGTHS)]))
        left = (count - used[video]) // step
        turn += 1
        if left < least:
            idle += 1
            continue
        idle = 0
        frames = min(wanted, left)
        plan.append(Segment(video, used[video], step, start, start + frames))
        used[video] += frames * step
        start += frames
    return plan


def write_splice(plan: list[Segment], out_path: Path, width_px: int = 1280, height_px: int = 720) -> list[Segment]:
    """Write the spliced video (mp4v, 25 fps); returns the segments as written (a video may end early)."""
    writer = open_video_writer(out_path, TARGET_FPS, (width_px, height_px))
    captures: dict[Path, cv2.VideoCapture] = {}
    written: list[Segment] = []
    index = 0
    try:
        for segment in plan:
            capture = captures.get(segment.video)
            if capture is None:
                capture = captures[segment.video] = cv2.VideoCapture(str(segment.video))
                capture.set(cv2.CAP_PROP_POS_FRAMES, segment.source_start)
            start = index
            for _ in range(segment.frames):
                image = None
                for _ in range(segment.step):
                    ok, frame = capture.read()
                    image = frame if ok else None
                    if image is None:
                        break
                if image is None:
                    break
                if image.shape[:2] != (height_px, width_px):
                    image = cv2.resize(image, (width_px, height_px), interpolation=cv2.INTER_AREA)
                writer.write(image)
                index += 1
            if index > start:
                written.append(Segment(segment.video, segment.source_start, segment.step, start, index))
    finally:
        writer.release()
        for capture in captures.values():
            capture.release()
    return written


def splice_shots(segments: list[Segment]) -> list[Shot]:
    """The splice's true shots (one per segment; kind unknown: "main")."""
    return [Shot(s.start, s.end, "main", s.video.stem, "start" if i == 0 else "hard", {})
            for i, s in enumerate(segments)]


def score_splice(video: Path, run_dir: Path, segments: list[Segment], wall_s: float,
                 config: AlignmentConfig = AlignmentConfig()) -> dict:
    """The figures of the tracked splice (module docstring)."""
    folder = RunFolder(run_dir)
    track = folder.read_track()
    records = {r.frame_index: r for r in track.records}
    summary = track.summary
    ids = read_frame_camera_ids(run_dir)
    curves = fitting_curves(PitchTemplate())
    aligned: dict[int, bool] = {}
    capture = cv2.VideoCapture(str(video))
    index = 0
    while True:
        ok, image = capture.read()
        if not ok:
            break
        record = records.get(index)
        if record is not None and record.camera is not None:
            alignment = line_alignment(image, record.camera, curves, config, line_pixels(image, config))
            aligned[index] = alignment is not None and alignment.aligned(config)
        index += 1
    capture.release()
    frames = len(records)
    reinit_s = (summary.get("timings_s") or {}).get("reinit_s")
    predicted = read_shots(run_dir / SHOTS_FILE) if (run_dir / SHOTS_FILE).is_file() else []
    per_segment = []
    for segment in segments:
        rows = range(segment.start, segment.end)
        with_camera = [i for i in rows if i in records and records[i].camera is not None]
        per_segment.append({
            "source": segment.video.name, "start": segment.start, "end": segment.end,
            "source_start": segment.source_start, "source_step": segment.step,
            "frames_with_camera": len(with_camera),
            "aligned_share": round(sum(aligned.get(i, False) for i in with_camera) / len(with_camera), 3)
            if with_camera else None,
            "camera_ids": dict(Counter(str(ids.get(i)) for i in with_camera)),
            "status_counts": dict(Counter(records[i].status for i in rows if i in records)),
        })
    return {
        "video": str(video), "frames": frames, "wall_s": round(wall_s, 2),
        "fps": round(frames / wall_s, 2) if wall_s > 0 else None,
        "reinit_time_share": round(reinit_s / wall_s, 4) if reinit_s is not None and wall_s > 0 else None,
        "status_counts": dict(Counter(r.status for r in track.records)),
        "cuts": cut_scores(splice_shots(segments), predicted),
        "segments": per_segment,
    }


def real_section(video_dir: Path, work_dir: Path, segment_frames: int = 120, segments: int = 6,
                 width_px: int = 1280, height_px: int = 720, progress: bool = True,
                 options: dict | None = None) -> dict:
    """Splice the videos of ``video_dir`` under ``work_dir``, track online (``options``: TrackingConfig fields), score
    (module docstring)."""
    from broadtrack_graph.actions.track import track_input
    from broadtrack_graph.track.config import TrackingConfig

    videos = sorted(Path(video_dir).glob("*.mp4"))
    if not videos:
        raise InputError(video_dir, "no *.mp4 video in this folder")
    plan = write_splice(splice_plan(videos, segment_frames, segments), work_dir / "splice.mp4", width_px, height_px)
    run_dir = work_dir / "run-online"
    started = time.perf_counter()
    track_input(work_dir / "splice.mp4", run_dir, TrackingConfig(mode="online", **(options or {})), progress=progress)
    wall_s = time.perf_counter() - started
    return score_splice(work_dir / "splice.mp4", run_dir, plan, wall_s)
