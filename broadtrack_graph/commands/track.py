"""``broadtrack-graph track``: track a clip (video, image folder, game-state sequence, or detections file)."""

from __future__ import annotations

from pathlib import Path

from broadtrack_graph.actions.track import track_input
from broadtrack_graph.commands.console import finish_run, print_interrupted_summary
from broadtrack_graph.commands.tracking_options import (
    add_tracking_arguments,
    config_from_args,
    detector_options,
    set_opencv_threads,
    tripod_from_args,
    tripods_from_args,
)
from broadtrack_graph.errors import InputError
from broadtrack_graph.io.tripod_file import TRIPOD_FILE

HELP = "track a clip online, with a fixed-lag smoother, or offline (two passes + batch refinement)"


def add_arguments(parser) -> None:
    parser.add_argument("input", nargs="?", type=Path,
                        help="video file, folder of numbered frames, or game-state sequence folder (img1/ + Labels-GameState.json)")
    parser.add_argument("--out", required=True, type=Path, help="run folder to write")
    parser.add_argument("--detections", type=Path, help="track from a detections file (JSON lines) instead of a detector")
    parser.add_argument("--frames", type=Path, help="with --detections: the frames too (turns optical flow on)")
    parser.add_argument("--write-960x540", action="store_true", help="also write cameras at 960x540")
    parser.add_argument("--players", default=None, metavar="FILE|detector",
                        help="also put players on the pitch as the run goes (players.jsonl beside track.jsonl, frame "
                             "by frame; game-state predictions and players_summary.json at the end): "
                             "a box file (Labels-GameState.json, MOT .txt, detections .jsonl) or 'detector' for the "
                             "detector's own player blobs")
    parser.add_argument("--pixel-sigma", type=float, default=2.0,
                        help="with --players: foot-point noise per image axis, pixels (default 2)")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    add_tracking_arguments(parser)


def run(args) -> int:
    if args.detections is None and args.input is None:
        raise InputError(None, "give an INPUT (video, frame folder or game-state folder) or --detections FILE")
    frames = args.frames or args.input  # with --detections the frames are optional (they turn flow on)
    config = config_from_args(args)
    set_opencv_threads(args)
    detector = detector_options(args)
    tripod, position = tripod_from_args(args)
    players_options = None
    if args.players is not None:
        from broadtrack_graph.actions.players import PlayersOptions

        players_options = PlayersOptions(pixel_sigma_px=args.pixel_sigma)
    try:
        result = track_input(frames, args.out, config, detector, tripod=tripod, reinit_position=position,
                             tripods=tripods_from_args(args), detections_path=args.detections, start=args.start,
                             end=args.end, progress=not args.no_progress, players=args.players,
                             players_options=players_options)
    except KeyboardInterrupt:
        print_interrupted_summary("track", args.out)
        raise
    summary = result.summary
    print(f"tracked {summary.get('frames_written', 0)} frames into {result.out_dir} ({summary.get('fps_two_passes') or summary.get('fps') or 0:.1f} fps)")
    if summary.get("note"):
        print(f"  {summary['note']}")
    players = summary.get("players")
    if players:
        print(f"  players: {players['located']} of {players['boxes']} boxes located (players.jsonl)")
    if result.tripod is not None:
        print(f"  tripod T = {[round(v, 2) for v in result.tripod.T_w]} m, delta = {result.tripod.delta_m:.3f} m "
              f"(written to {result.out_dir / TRIPOD_FILE})")
    return finish_run("track", summary)
