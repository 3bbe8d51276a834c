"""``broadtrack-graph track``: track a clip (video, image folder, game-state sequence, or detections file)."""

from __future__ import annotations

import logging
from pathlib import Path

from broadtrack_graph.errors import InputError
from broadtrack_graph.actions.track import DetectorOptions, track_input
from broadtrack_graph.io.tripod_file import read_tripod
from broadtrack_graph.track.config import MODES, TrackingConfig
from broadtrack_graph.geometry.tripod import Tripod

HELP = "track a clip online, with a fixed-lag smoother, or offline (two passes + batch refinement)"
log = logging.getLogger(__name__)


def add_tracking_arguments(parser) -> None:
    """Options shared by track, detect and the benchmarks."""
    parser.add_argument("--mode", choices=MODES, default="online", help="online (iSAM2), fixed-lag, or batch (default online)")
    parser.add_argument("--lag", type=int, default=25, help="fixed-lag: frames of future used (default 25)")
    tripod = parser.add_mutually_exclusive_group()
    tripod.add_argument("--tripod", type=Path, help="tripod.json of an earlier run of this camera")
    tripod.add_argument("--tripod-position", type=float, nargs=3, metavar=("X", "Y", "Z"),
                        help="known pan/tilt centre in metres (SoccerNet frame, z down); delta is fitted")
    parser.add_argument("--detector", choices=("weightfree", "onnx"), default="weightfree", help="field detector (default weightfree)")
    parser.add_argument("--segmentation-model", type=Path, help="ONNX line-segmentation model (with its .json contract)")
    parser.add_argument("--keypoint-model", type=Path, help="ONNX keypoint-heatmap model (with its .json contract)")
    parser.add_argument("--start", type=int, default=None, help="first frame index (0-based, inclusive)")
    parser.add_argument("--end", type=int, default=None, help="last frame index (exclusive)")
    parser.add_argument("--no-flow", action="store_true", help="switch the optical-flow factor off")
    parser.add_argument("--no-tripod", action="store_true", help="switch the tripod factor off")
    parser.add_argument("--no-k1", action="store_true", help="hold radial distortion k1 at 0")
    parser.add_argument("--confidence-threshold", type=float, default=0.5, help="re-initialise below this (default 0.5)")
    parser.add_argument("--batch-tripod", choices=("fixed", "joint"), default="fixed",
                        help="batch: hold the first pass's tripod fixed in the refinement (default) or re-estimate it jointly")


def add_arguments(parser) -> None:
    parser.add_argument("input", nargs="?", type=Path,
                        help="video file, folder of numbered frames, or game-state sequence folder (img1/ + Labels-GameState.json)")
    parser.add_argument("--out", required=True, type=Path, help="run folder to write")
    parser.add_argument("--detections", type=Path, help="track from a detections file (JSON lines) instead of a detector")
    parser.add_argument("--frames", type=Path, help="with --detections: the frames too (turns optical flow on)")
    parser.add_argument("--write-960x540", action="store_true", help="also write cameras at 960x540")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    add_tracking_arguments(parser)


def config_from_args(args) -> TrackingConfig:
    return TrackingConfig(mode=args.mode, lag_frames=args.lag, use_flow=not args.no_flow, use_tripod=not args.no_tripod,
                          estimate_k1=not args.no_k1, confidence_threshold=args.confidence_threshold,
                          batch_tripod=getattr(args, "batch_tripod", "fixed"),
                          write_960x540=getattr(args, "write_960x540", False))


def tripod_from_args(args) -> tuple[Tripod | None, tuple | None]:
    """(known tripod, known position only)."""
    if args.tripod is not None:
        return read_tripod(args.tripod), None
    if args.tripod_position is not None:
        return None, tuple(args.tripod_position)
    return None, None


def detector_options(args) -> DetectorOptions:
    if args.detector == "onnx" and args.segmentation_model is None and args.keypoint_model is None:
        raise InputError(None, "--detector onnx needs --segmentation-model and/or --keypoint-model")
    return DetectorOptions(args.detector, args.segmentation_model, args.keypoint_model)


def run(args) -> int:
    if args.detections is None and args.input is None:
        raise InputError(None, "give an INPUT (video, frame folder or game-state folder) or --detections FILE")
    frames = args.frames or args.input  # with --detections the frames are optional (they turn flow on)
    tripod, position = tripod_from_args(args)
    result = track_input(frames, args.out, config_from_args(args), detector_options(args), tripod=tripod,
                         tripod_position=position, detections_path=args.detections, start=args.start, end=args.end,
                         progress=not args.no_progress)
    summary = result.summary
    print(f"tracked {summary.get('frames_written', 0)} frames into {result.out_dir} ({summary.get('fps', 0):.1f} fps)")
    counts = summary.get("status_counts", {})
    if counts:
        print("  " + ", ".join(f"{k}: {v}" for k, v in counts.items() if v))
    if result.tripod is not None:
        print(f"  tripod T = {[round(v, 2) for v in result.tripod.T_w]} m, delta = {result.tripod.delta_m:.3f} m "
              f"(written to {result.out_dir / 'tripod.json'})")
    return 0
