"""Track what the user gives: open the input, build the detector, run the pipeline.

The library entry point behind ``broadtrack-graph track`` (and ``detect``):
:func:`track_input` for a path, :func:`run_frames` (in :mod:`broadtrack_graph.track.passes`)
for frames already in memory. :func:`track_input` is where the run's
:class:`~broadtrack_graph.track.run_context.RunContext` is built, once, from what the user gives.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path

from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.io.detections import read_detections
from broadtrack_graph.io.frames import open_frames
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.inputs import frames_from_detections, frames_from_source
from broadtrack_graph.track.passes import run_frames
from broadtrack_graph.track.result import RunResult
from broadtrack_graph.track.run_context import RunContext

DETECTOR_BOXES = "detector"
"""``players`` value of :func:`track_input` meaning the detector's own player blobs."""


@dataclass(frozen=True)
class DetectorOptions:
    """Which field detector to run on frames."""

    kind: str = "weightfree"  # weightfree | onnx
    segmentation_model: Path | None = None  # ONNX line-segmentation model
    keypoint_model: Path | None = None  # ONNX keypoint-heatmap model
    field_model: Path | None = None  # ONNX field model: keypoints and lines in one (not with the other two)
    faint_look: bool = True  # weight-free: the court model's second look at a lost frame (detect.faint_lines)


def make_detector(options: DetectorOptions, pitch: PitchTemplate | None = None):
    """The detector described by the options (ONNX models are checked against their contract)."""
    if options.kind == "weightfree":
        from broadtrack_graph.detect.faint_lines import FaintLineConfig
        from broadtrack_graph.detect.weightfree import WeightFreeDetector
        from broadtrack_graph.detect.weightfree_config import WeightFreeConfig

        faint = FaintLineConfig() if options.faint_look else None
        return WeightFreeDetector(pitch, WeightFreeConfig(faint_lines=faint))
    if options.kind == "onnx":
        from broadtrack_graph.detect.onnx_detector import OnnxDetector

        for path in (options.segmentation_model, options.keypoint_model, options.field_model):
            if path is not None and not Path(path).is_file():
                raise InputError(path, "model file not found")
        return OnnxDetector(options.segmentation_model, options.keypoint_model, pitch=pitch,
                            field_model=options.field_model)
    raise InputError(None, f"unknown detector '{options.kind}' (weightfree or onnx)")


def track_input(
    frames_path: str | Path | None,
    out_dir: str | Path,
    config: TrackingConfig = TrackingConfig(),
    detector: DetectorOptions = DetectorOptions(),
    tripod: Tripod | None = None,
    reinit_position=None,
    detections_path: str | Path | None = None,
    start: int | None = None,
    end: int | None = None,
    progress: bool = True,
    pitch: PitchTemplate | None = None,
    players: str | Path | None = None,
    players_options=None,
    tripods: dict[str, Tripod] | None = None,
) -> RunResult:
    """Track a video / frame folder / game-state sequence, or a detections file (with or without frames).

    What the user gives becomes the run's :class:`~broadtrack_graph.track.run_context.RunContext` here, once; the
    layers below (the passes, each tracking run) take only the context.

    Args:
        frames_path: the frames (None with a detections file alone: no optical flow).
        out_dir: run folder.
        config: tracking options (mode, lag, switches).
        detector: detector for image input (unused with a detections file).
        tripod: known tripod, or None; reinit_position: a guess (x, y, z metres) of the camera position for re-initialisation, not a tripod constraint.
        detections_path: a detections file (JSON lines) to track from instead of a detector.
        start, end: frame range (0-based, end exclusive).
        players: put players on the pitch too: a box file (game-state labels, MOT, detections), or
            :data:`DETECTOR_BOXES` for the player blobs the detector finds (or the detections file holds;
            linked into tracks as they come); each frame's players are located and appended to
            ``players.jsonl`` as its record is written, beside every ``track.jsonl`` the run writes, and the
            game-state predictions and players summary come from the final cameras at the end
            (:mod:`broadtrack_graph.actions.players_live`).
        players_options: a :class:`~broadtrack_graph.actions.players.PlayersOptions` (default options).
        tripods: known tripods by camera id of the shots (image input), e.g. {"main": ...}.
    """
    live = None
    if players is not None:
        from broadtrack_graph.actions.players import PlayersOptions
        from broadtrack_graph.actions.players_live import LivePlayers

        live = LivePlayers(None if str(players) == DETECTOR_BOXES else Path(players), players_options or PlayersOptions())
    try:
        positions = None if reinit_position is None else [tuple(float(v) for v in reinit_position)]
        context = RunContext(config, pitch=pitch, tripod=tripod, tripods=tripods, reinit_positions=positions,
                             progress=progress)
        result = _track(frames_path, detections_path, start, end, out_dir, context, detector, live)
    except BaseException:
        if live is not None:
            live.close()  # an interrupted or failed run keeps the players of every frame it wrote
        raise
    if live is not None:
        located = live.finish(result.out_dir, progress)
        result.summary["players"] = {k: located.summary[k] for k in ("boxes", "located", "no_camera", "analytics")}
    return result


def _track(frames_path, detections_path, start, end, out_dir, context: RunContext, detector: DetectorOptions,
           players) -> RunResult:
    """Open the input and run the passes with the context (completed here: the detector for frames, the masks a
    detections file names, the run's description); ``players`` (a LivePlayers, or None) locates the players as
    records are written (its box file is read before the first frame)."""
    run_info = {"input": None if frames_path is None else str(frames_path),
                "detections": None if detections_path is None else str(detections_path),
                "detector": None if detections_path is not None else detector.kind}
    if detections_path is not None:
        window = (start, end) if frames_path is None and (start is not None or end is not None) else None
        detections = read_detections(detections_path, context.pitch, frame_range=window)
        source = open_frames(frames_path, start, end) if frames_path is not None else None
        try:
            width, height = (source.width_px, source.height_px) if source is not None else detections.image_size
            total = len(source) if source is not None else None
            frames = frames_from_detections(detections, 25.0 if source is None else source.fps, start, end, source)
            run_info["detection_issues"] = len(detections.issues)
            # (tripods by camera id are for image input: the ids of its shots)
            context = replace(context, tripods=None, run_info=run_info, mask_paths=detections.mask_paths,
                              **_player_observers(players, width, height, out_dir))
            return run_frames(frames, width, height, out_dir, context, total)
        finally:
            if source is not None:
                source.close()
    if frames_path is None:
        raise InputError(None, "no input frames given")
    with open_frames(frames_path, start, end) as source:
        run_info["source"] = source.describe()
        context = replace(context, detector=make_detector(detector, context.pitch), run_info=run_info,
                          **_player_observers(players, source.width_px, source.height_px, out_dir))
        return run_frames(frames_from_source(source), source.width_px, source.height_px, out_dir, context,
                          len(source), source)


def _player_observers(players, width_px: int, height_px: int, out_dir) -> dict:
    """The run context's observers that locate the players as the run goes (none without players); reads the
    boxes."""
    if players is None:
        return {}
    players.start(width_px, height_px, out_dir)
    return {"record_observer": players.observer_for,
            "on_frame_done": players.frame_done if players.from_detector else None}
