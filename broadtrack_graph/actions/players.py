"""Players on the pitch from a run's cameras (the ``players`` command; ``track --players`` locates each frame with
:func:`frame_lines` as it is written, :mod:`broadtrack_graph.actions.players_live`).

For every frame of the boxes, the frame's camera (matched by frame id, else by frame
index) back-projects each box's bottom middle and bottom corners to the ground
(:func:`broadtrack_graph.geometry.ground.foot_positions`); the position's standard
deviation combines the camera's marginal standard deviations of ``track.jsonl``
(diagonal: the file keeps no correlations) and a foot-point pixel noise
(``pixel_sigma_px``, default 2 px per axis). Written to OUT:

* ``players.jsonl`` (:mod:`broadtrack_graph.io.players_file`), flushed per frame;
* ``predictions-gamestate.json``: SoccerNet game-state predictions with ``bbox_pitch``;
* ``players_summary.json``: counts, the issues (the first 1000), per-track distance / top speed / jitter
  (:mod:`broadtrack_graph.metrics.players`);
* ``birdseye_players.mp4`` on request (:mod:`broadtrack_graph.products.players_view`).

A box frame the run does not know, a box whose foot misses the ground (above the
horizon, too far, outside the lens model) is reported one line each and gets no
position; a frame without a camera gives its boxes no position, with the frame's
status and reason.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from tqdm import tqdm

from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.ground import DEFAULT_MAX_DISTANCE_M, GROUND_OK, foot_positions
from broadtrack_graph.io.jsonfile import write_json_atomic
from broadtrack_graph.io.player_boxes import read_player_boxes
from broadtrack_graph.io.players_file import (
    PLAYERS_FILE,
    PREDICTIONS_FILE,
    PlayersWriter,
    player_line,
    positions_from_lines,
    write_gamestate_predictions,
)
from broadtrack_graph.io.run_folder import read_track
from broadtrack_graph.metrics.players import AnalyticsConfig, analytics_summary, fps_from_times, track_analytics
from broadtrack_graph.types.player_boxes import PlayerBoxes, PlayerFrame
from broadtrack_graph.types.track_record import RunRecords, TrackRecord, covariance_from_std

log = logging.getLogger(__name__)

SUMMARY_FILE = "players_summary.json"
VIDEO_FILE = "birdseye_players.mp4"
MAX_LOGGED_ISSUES = 20
MAX_SUMMARY_ISSUES = 1000


@dataclass(frozen=True)
class PlayersOptions:
    """How boxes become pitch positions."""

    pixel_sigma_px: float = 2.0  # standard deviation of the foot point per image axis, pixels
    max_distance_m: float = DEFAULT_MAX_DISTANCE_M  # feet farther from the camera get no position (near the horizon)
    smooth_frames: int = 5  # analytics: centred moving average over this many frames
    video: bool = False  # also write the bird's-eye video of the players
    video_width_px: int = 960  # width of that video


@dataclass
class PlayersResult:
    """What :func:`players_from_run` wrote and counted."""

    out_dir: Path
    boxes: int = 0
    located: int = 0
    no_camera: int = 0
    issues: list[str] = field(default_factory=list)
    summary: dict = field(default_factory=dict)
    lines: list[dict] = field(default_factory=list)

    def add(self, located: "FrameLines") -> None:
        """Count one located box frame and keep its lines and issues."""
        self.lines.extend(located.lines)
        self.issues.extend(located.issues)
        self.located += located.located
        self.no_camera += located.no_camera


def clip_fps(track: RunRecords, default: float = 25.0) -> float:
    """Frames per second of a run from its records' times (:func:`~broadtrack_graph.metrics.players.fps_from_times`)."""
    times = np.array([np.nan if r.time_s is None else r.time_s for r in track.records], dtype=float)
    return fps_from_times(times, track.frame_indices, default)


def locate_players(track: RunRecords, boxes: PlayerBoxes, options: PlayersOptions = PlayersOptions(),
                   writer: PlayersWriter | None = None, progress: bool = False) -> PlayersResult:
    """Pitch positions of every box with its frame's camera (see the module docstring).

    Args:
        track: the run read back (cameras at its resolution).
        boxes: the player boxes (rescaled to the run's resolution when their size is known).
        writer: where each frame's lines go as they are made (None: kept in memory only).

    Returns:
        PlayersResult with the ``players.jsonl`` objects in ``lines`` and one issue line per skipped item.
    """
    boxes = boxes.scaled(track.width_px, track.height_px)
    by_id = track.by_frame_id()
    by_index = {r.frame_index: r for r in track.records}
    result = PlayersResult(Path("."), issues=list(boxes.issues))
    for frame in tqdm(boxes.frames, desc="players", unit="frame", disable=not progress):
        record = by_id.get(frame.frame_id) if frame.frame_id is not None else None
        if record is None and frame.frame_index is not None:
            record = by_index.get(frame.frame_index)
        result.boxes += len(frame)
        if record is None:
            result.issues.append(not_in_run_issue(boxes.source, frame))
            continue
        located = frame_lines(record, frame, boxes.source, options)
        result.add(located)
        if writer is not None:
            writer.write_frame(located.lines)
    return result


@dataclass
class FrameLines:
    """The ``players.jsonl`` objects of one box frame located with one record, and what was counted."""

    lines: list[dict]
    issues: list[str]
    located: int = 0  # boxes with a position
    no_camera: int = 0  # boxes of a frame without a camera


def not_in_run_issue(source: str, frame: PlayerFrame) -> str:
    """The one-line issue of a box frame no record of the run matches."""
    name = frame.frame_id if frame.frame_id is not None else f"index {frame.frame_index}"
    return f"{source}: frame {name} is not in the run; its {len(frame)} box(es) skipped"


def frame_lines(record: TrackRecord, frame: PlayerFrame, source: str, options: PlayersOptions) -> FrameLines:
    """Locate one frame's boxes with its record's camera and marginal standard deviations (see the module docstring).

    Args:
        record: the frame's record as ``track.jsonl`` holds it (camera at the run's resolution, or None).
        frame: its boxes (N, 4) pixels at the run's resolution.
        source: the boxes' source, named in the issue lines.
    """
    out = FrameLines([], [])
    if record.camera is None:
        out.no_camera = len(frame)
        for i in range(len(frame)):
            out.lines.append(player_line(record.frame_index, record.frame_id, frame.track_ids[i], frame.boxes_px[i],
                                         frame.roles[i], frame.teams[i], None, None, None, None, record.status,
                                         record.reason or f"no camera ({record.status})"))
        return out
    located = foot_positions(record.camera, frame.boxes_px, covariance_from_std(record.std),
                             options.pixel_sigma_px, options.max_distance_m)
    for i in range(len(frame)):
        reason = located["reasons"][i]
        ok = reason == GROUND_OK
        if not ok:
            out.issues.append(f"{source}: frame {record.frame_id} track {frame.track_ids[i]} box "
                              f"{np.round(frame.boxes_px[i], 1).tolist()}: foot {reason}; no position")
        out.located += int(ok)
        out.lines.append(player_line(record.frame_index, record.frame_id, frame.track_ids[i], frame.boxes_px[i],
                                     frame.roles[i], frame.teams[i], located["xy_m"][i] if ok else None,
                                     located["std_m"][i], located["left_m"][i], located["right_m"][i], record.status,
                                     None if ok else str(reason)))
    return out


def players_from_run(run_dir: str | Path, boxes: str | Path | PlayerBoxes, out_dir: str | Path | None = None,
                     options: PlayersOptions = PlayersOptions(), progress: bool = True) -> PlayersResult:
    """Locate a run's players and write players.jsonl, the game-state predictions and the summary.

    Args:
        run_dir: run folder (track.jsonl) or folder of camera files.
        boxes: a box file (:func:`~broadtrack_graph.io.player_boxes.read_player_boxes`) or boxes in memory.
        out_dir: output folder (default: the run folder).
        options: pixel noise, distance limit, analytics smoothing, video.

    Raises:
        InputError: the run or the boxes cannot be read, or the output cannot be written.
    """
    track = read_track(run_dir)
    if not isinstance(boxes, PlayerBoxes):
        boxes = read_player_boxes(boxes, image_size=(track.width_px, track.height_px))
    out = Path(out_dir) if out_dir is not None else Path(run_dir)
    try:
        out.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(out, f"cannot create output folder: {exc.strerror or exc}") from None
    with PlayersWriter(out / PLAYERS_FILE) as writer:
        result = locate_players(track, boxes, options, writer, progress)
    result.out_dir = out
    write_players_outputs(track, boxes, result, options, str(run_dir), progress)
    return result


def write_players_outputs(track: RunRecords, boxes: PlayerBoxes, result: PlayersResult, options: PlayersOptions,
                          run_label: str, progress: bool = True) -> None:
    """Everything but ``players.jsonl`` from the located lines: the game-state predictions, the summary (stored in
    ``result.summary``), the video on request; written to ``result.out_dir``.

    Args:
        track: the run whose cameras located the boxes (its frame times give the fps).
        boxes: the boxes located (source, kind, the image ids of game-state labels).
        result: the lines, counts and issues, in the order of the box frames.
        run_label: the run named in the summary.
    """
    out = result.out_dir
    predictions = write_gamestate_predictions(out / PREDICTIONS_FILE, result.lines, boxes.image_ids)
    for issue in result.issues[:MAX_LOGGED_ISSUES]:
        log.warning(issue)
    if len(result.issues) > MAX_LOGGED_ISSUES:
        log.warning("... %d more issues in %s", len(result.issues) - MAX_LOGGED_ISSUES, out / SUMMARY_FILE)
    positions = positions_from_lines(result.lines)
    fps = clip_fps(track)
    per_track = track_analytics(positions.frame, positions.track_id, positions.xy_m,
                                AnalyticsConfig(fps=fps, smooth_frames=options.smooth_frames))
    std = positions.std_m[positions.has_position]
    result.summary = {
        "run": run_label, "boxes_source": boxes.source, "boxes_kind": boxes.kind, "fps": round(fps, 3),
        "pixel_sigma_px": options.pixel_sigma_px, "boxes": result.boxes, "located": result.located,
        "no_camera": result.no_camera, "predictions": predictions,
        "median_std_m": None if not len(std) else [round(float(v), 4) for v in np.median(std, axis=0)],
        "analytics": {"smoothing": f"centred moving average over {options.smooth_frames} frames",
                      **analytics_summary(per_track)},
        "tracks": {str(k): {kk: (round(vv, 4) if isinstance(vv, float) and np.isfinite(vv) else
                                 (None if isinstance(vv, float) else vv)) for kk, vv in v.items()}
                   for k, v in per_track.items()},
        "issue_count": len(result.issues),
        "issues": result.issues[:MAX_SUMMARY_ISSUES],
    }
    write_json_atomic(out / SUMMARY_FILE, result.summary, indent=2)
    if options.video:
        from broadtrack_graph.products.players_view import write_players_birdseye

        write_players_birdseye(track, positions, out / VIDEO_FILE, fps, options.video_width_px, progress)
