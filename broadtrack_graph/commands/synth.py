"""``broadtrack-graph synth``: render a synthetic broadcast clip with exact ground truth."""

from __future__ import annotations

from pathlib import Path

from broadtrack_graph.arguments import image_side, int_at_least, int_between
from broadtrack_graph.errors import InputError
from broadtrack_graph.synth.presets import PRESETS

HELP = "render a synthetic broadcast clip (frames, cameras, SoccerNet annotations, masks, keypoints)"


def add_arguments(parser) -> None:
    parser.add_argument("--preset", default="main", choices=sorted(PRESETS) + ["broadcast"],
                        help="camera and play preset, or broadcast: cuts between several cameras, close-ups and crowd shots (default main)")
    parser.add_argument("--frames", type=int_at_least(1), default=750, help="number of frames (default 750, 30 s at 25 fps); with --cameras at most this many")
    parser.add_argument("--width", type=image_side, default=1920, help="image width in pixels (default 1920)")
    parser.add_argument("--height", type=image_side, default=1080, help="image height in pixels (default 1080)")
    parser.add_argument("--seed", type=int, default=0, help="random seed; same seed, same clip (default 0)")
    parser.add_argument("--out", type=Path, required=True, help="output folder (SoccerNet game-state layout)")
    parser.add_argument("--cameras", type=Path, default=None,
                        help="render along this folder of camera_NNNNN.json files instead of a generated track")
    parser.add_argument("--jpeg-quality", type=int_between(1, 100), default=90, help="JPEG quality of the frames (default 90)")
    parser.add_argument("--mp4", action="store_true", help="also write clip.mp4 (mp4v)")
    parser.add_argument("--no-masks", action="store_true", help="do not write the per-class line masks")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")


def run(args) -> int:
    from broadtrack_graph.synth.writer import write_synthetic_clip  # imports the renderer: only when run

    if args.frames < 1 or args.width < 16 or args.height < 16:
        raise InputError(None, f"--frames must be >= 1 and the size at least 16x16, got {args.frames} frames of "
                               f"{args.width}x{args.height}")
    if args.preset == "broadcast":
        from broadtrack_graph.synth.broadcast import DEFAULT_PLAN

        if args.cameras is not None:
            raise InputError(args.cameras, "--preset broadcast generates its own cameras; leave out --cameras")
        if args.frames < 2 * len(DEFAULT_PLAN):
            raise InputError(None, f"--preset broadcast has {len(DEFAULT_PLAN)} shots of at least 2 frames: give "
                                   f"--frames {2 * len(DEFAULT_PLAN)} or more, got {args.frames}")
    summary = write_synthetic_clip(
        args.out, preset=args.preset, frame_count=args.frames, width_px=args.width, height_px=args.height,
        seed=args.seed, cameras_dir=args.cameras, jpeg_quality=args.jpeg_quality, write_mp4=args.mp4,
        write_masks=not args.no_masks, progress=not args.no_progress,
    )
    print(f"wrote {summary.frames_written} frames of {args.width}x{args.height} to {summary.out_dir} "
          f"in {summary.seconds:.1f} s ({summary.seconds_per_frame:.3f} s/frame)")
    return 0
