"""``broadtrack-graph players``: player positions on the pitch from a run's cameras and a box file."""

from __future__ import annotations

from pathlib import Path

from broadtrack_graph.actions.players import PlayersOptions, players_from_run

HELP = "put players on the pitch: boxes (game-state labels, MOT, detections file) through a run's cameras"


def add_arguments(parser) -> None:
    parser.add_argument("run", type=Path, help="run folder (track.jsonl) or a folder of camera_*.json files")
    parser.add_argument("--boxes", required=True, type=Path,
                        help="player boxes: Labels-GameState.json (or its folder), MOT .txt/.csv, or a detections .jsonl")
    parser.add_argument("--out", type=Path, default=None, help="output folder (default: the run folder)")
    parser.add_argument("--pixel-sigma", type=float, default=PlayersOptions.pixel_sigma_px,
                        help=f"foot-point noise per image axis, pixels (default {PlayersOptions.pixel_sigma_px:g})")
    parser.add_argument("--smooth-frames", type=int, default=PlayersOptions.smooth_frames,
                        help="analytics: centred moving average over this many frames (default "
                             f"{PlayersOptions.smooth_frames}; 1 = none)")
    parser.add_argument("--video", action="store_true", help="also write birdseye_players.mp4")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")


def run(args) -> int:
    options = PlayersOptions(pixel_sigma_px=args.pixel_sigma, smooth_frames=max(1, args.smooth_frames), video=args.video)
    result = players_from_run(args.run, args.boxes, args.out, options, progress=not args.no_progress)
    s = result.summary
    print(f"{s['located']} of {s['boxes']} boxes located ({s['no_camera']} in frames without a camera, "
          f"{len(result.issues)} issues) -> {result.out_dir}")
    a = s["analytics"]
    if a.get("tracks"):
        print(f"  {a['tracks']} tracks, {a['total_distance_m']:.1f} m covered in total, median top speed "
              f"{a['median_top_speed_m_s']} m/s, median jitter {a['median_jitter_rms_m']} m ({a['smoothing']})")
    return 0
