"""``broadtrack-graph demo``: the README's main command (see broadtrack_graph.actions.demo)."""

from __future__ import annotations

from pathlib import Path

from broadtrack_graph.actions.demo import DemoSettings, run_demo
from broadtrack_graph.arguments import image_side, int_at_least
from broadtrack_graph.commands.tracking_options import set_opencv_threads

HELP = "render the embedded synthetic clip, track it online and smoothed, evaluate, draw and compare"


def add_arguments(parser) -> None:
    parser.add_argument("--out", type=Path, default=Path("runs/demo"), help="output folder (default runs/demo)")
    parser.add_argument("--frames", type=int_at_least(2), default=DemoSettings.frames,
                        help=f"clip length (default {DemoSettings.frames})")
    parser.add_argument("--width", type=image_side, default=DemoSettings.width_px,
                        help=f"frame width (default {DemoSettings.width_px})")
    parser.add_argument("--height", type=image_side, default=DemoSettings.height_px,
                        help=f"frame height (default {DemoSettings.height_px})")
    parser.add_argument("--seed", type=int, default=DemoSettings.seed, help=f"clip seed (default {DemoSettings.seed})")
    parser.add_argument("--no-overlay", action="store_true", help="skip the overlay video")
    parser.add_argument("--no-progress", action="store_true", help="hide progress bars")


def run(args) -> int:
    set_opencv_threads(args)  # as `track`: the cores the tracking and decoding threads leave
    settings = DemoSettings(frames=args.frames, width_px=args.width, height_px=args.height, seed=args.seed,
                            overlay=not args.no_overlay)
    result = run_demo(args.out, settings, progress=not args.no_progress)
    print()
    print(result["table"])
    print()
    reused = " (reused: same preset, seed, size and length)" if result["clip_reused"] else ""
    print(f"synthetic clip (frames, ground truth): {result['clip']}{reused}")
    for name, path in result["runs"].items():
        print(f"{name} run (cameras/, track.jsonl, summary.json): {path}")
    print(f"comparison (compare.md, compare.json, series.png, focal_points.png): {result['compare']}")
    if result["overlay"]:
        print(f"overlay video: {result['overlay']}")
    print(f"disk use: {result['disk_mb']:.0f} MB in {args.out} (the clip: {result['clip_disk_mb']:.0f} MB, "
          f"kept for the next demo run; delete the folder to free it)")
    return 0
