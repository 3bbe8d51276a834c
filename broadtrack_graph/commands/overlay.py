"""``broadtrack-graph overlay``: draw a run's cameras on its frames (mp4 or PNGs)."""

from __future__ import annotations

from pathlib import Path

from broadtrack_graph.arguments import frame_index

HELP = "draw the projected pitch (coloured by confidence) and a bird's-eye inset on the frames of a run"


def add_arguments(parser) -> None:
    parser.add_argument("run", type=Path, help="run folder (track.jsonl) or a folder of camera_*.json files")
    parser.add_argument("--frames", required=True, type=Path,
                        help="the input the run was made from: video, image folder or game-state sequence folder")
    parser.add_argument("--out", required=True, type=Path, help="output FILE.mp4, or a folder for PNG images")
    parser.add_argument("--start", type=frame_index, default=None, help="first input frame (0-based, inclusive)")
    parser.add_argument("--end", type=frame_index, default=None, help="last input frame (0-based, exclusive)")
    parser.add_argument("--no-inset", action="store_true", help="leave out the bird's-eye inset")
    parser.add_argument("--players", type=Path, default=None,
                        help="players.jsonl (or its folder) of the run: draw the players in the bird's-eye inset")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")


def run(args) -> int:
    from broadtrack_graph.products.overlay import write_overlay

    result = write_overlay(args.run, args.frames, args.out, args.start, args.end, inset=not args.no_inset,
                           progress=not args.no_progress, players_path=args.players)
    print(f"wrote {result['frames']} frames to {result['out']} "
          f"({result['with_camera']} with a camera, {result['missing_input']} unreadable input frames)")
    if result.get("cameras_from"):
        print(f"cameras read from {result['cameras_from']}")
    return 0
