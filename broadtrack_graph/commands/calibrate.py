"""``broadtrack-graph calibrate``: one camera per frame, from its annotation's line points or from images by the
learned field model alone."""

from __future__ import annotations

import json
import logging
from pathlib import Path

from broadtrack_graph.actions.calibrate import PREVIEW_FRAMES, calibrate_folder, calibrate_images
from broadtrack_graph.arguments import int_at_least
from broadtrack_graph.commands.console import EXIT_NO_CAMERA

log = logging.getLogger(__name__)

HELP = ("single-frame calibration: one camera file per frame, from each annotation file's line points "
        "(--annotations) or from images by the shipped field model alone (--images)")


def add_arguments(parser) -> None:
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--annotations", type=Path,
                        help="folder of per-image NNNNN.json annotations, or a Labels-GameState.json (or its folder)")
    source.add_argument("--images", type=Path,
                        help="a folder of images, a video or a game-state sequence: one camera per frame from the "
                             "learned field model alone (cameras at each frame's own size; --width/--height unused)")
    parser.add_argument("--model", type=Path, default=None,
                        help="with --images: a field model .onnx with its .json contract (default: the shipped one)")
    parser.add_argument("--out", required=True, type=Path, help="folder for camera_NNNNN.json files (created)")
    parser.add_argument("--width", type=int_at_least(2), default=960, help="image width in pixels the cameras are for (default 960)")
    parser.add_argument("--height", type=int_at_least(2), default=540, help="image height in pixels (default 540)")
    parser.add_argument("--jobs", type=int_at_least(1), default=1, help="worker processes (default 1)")
    parser.add_argument("--preview", type=Path, default=None,
                        help=f"write a PNG mosaic of {PREVIEW_FRAMES} evenly spaced frames: template, points within "
                             "5 px green, others red")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")


def run(args) -> int:
    if args.images is not None:
        summary = calibrate_images(args.images, args.out, args.model, preview_path=args.preview,
                                   progress=not args.no_progress)
    else:
        summary = calibrate_folder(args.annotations, args.out, args.width, args.height, jobs=args.jobs,
                                   preview_path=args.preview, progress=not args.no_progress)
    missing = summary.pop("missing")
    print(json.dumps({**summary, "missing_count": len(missing), "missing": dict(list(missing.items())[:20])}, indent=2))
    if summary["cameras"] == 0:
        log.error("no frame of %d could be calibrated (see \"missing\" above); exit code %d", summary["frames"],
                  EXIT_NO_CAMERA)
        return EXIT_NO_CAMERA
    return 0
