"""``broadtrack-graph detect``: write a detections file, from frames (the project's detector) or annotations."""

from __future__ import annotations

from pathlib import Path

from broadtrack_graph.arguments import frame_index, int_at_least
from broadtrack_graph.commands.console import warning_count
from broadtrack_graph.commands.tracking_options import (
    add_tracking_arguments,
    config_from_args,
    detector_options,
    set_opencv_threads,
    tripod_from_args,
)
from broadtrack_graph.errors import InputError

HELP = ("write a detections file (JSON lines) from frames with the project's detector, from SoccerNet annotations, "
        "or from NBJW / PnLCalib keypoint predictions")


def add_arguments(parser) -> None:
    parser.add_argument("input", nargs="?", type=Path,
                        help="video file, folder of numbered frames, or game-state sequence folder")
    parser.add_argument("--out", required=True, type=Path, help="detections file to write (.jsonl); masks go to <stem>_masks/")
    parser.add_argument("--annotations", type=Path,
                        help="instead of INPUT: import SoccerNet line annotations (folder of per-image JSON or "
                             "Labels-GameState.json) as line detections")
    parser.add_argument("--import", dest="import_kind", choices=["nbjw"], default=None,
                        help="instead of INPUT: import a published detector's per-frame predictions; nbjw = No Bells "
                             "Just Whistles / PnLCalib keypoint files (folder or zip of per-frame JSON); INPUT is "
                             "their folder or zip")
    parser.add_argument("--clip", default=None,
                        help="--import: the clip to import when the folder holds several (file stem without IMG_<n>)")
    parser.add_argument("--units", choices=["normalized", "px"], default="normalized",
                        help="--import: keypoint coordinates normalised by the image size (default) or pixels")
    parser.add_argument("--width", type=int_at_least(2), help="--annotations / --import: image width the coordinates refer to")
    parser.add_argument("--height", type=int_at_least(2), help="--annotations / --import: image height")
    parser.add_argument("--first-number", type=frame_index, default=None,
                        help="--annotations folder: number of the file of frame 0 (default 1, or 0 if a file 0 exists)")
    parser.add_argument("--no-masks", action="store_true", help="do not write the marking masks")
    parser.add_argument("--track-out", type=Path, default=None,
                        help="keep the run folder of the online tracker that names the markings")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")
    add_tracking_arguments(parser)


def run(args) -> int:
    from broadtrack_graph.actions.detect import export_detections, import_annotations, import_nbjw

    if args.import_kind is not None:
        if args.input is None or args.annotations is not None:
            raise InputError(None, "--import nbjw needs the predictions folder or zip as INPUT (and no --annotations)")
        summary = import_nbjw(args.input, args.out, args.width, args.height, clip=args.clip, units=args.units)
        print(f"imported {summary.records} frames ({summary.frames_with_keypoints} with keypoints) into {summary.path}"
              + (f" ({len(summary.skipped)} items left out, see the warnings)" if summary.skipped else ""))
        return 0
    if (args.input is None) == (args.annotations is None):
        raise InputError(None, "give either INPUT (frames) or --annotations SOURCE")
    if args.annotations is not None:
        summary = import_annotations(args.annotations, args.out, args.width, args.height, args.first_number)
        print(f"imported {summary.records} annotated frames into {summary.path}"
              + (f" ({len(summary.skipped)} items left out, see the warnings)" if summary.skipped else "")
              + f", {warning_count()} warnings")
        return 0
    config = config_from_args(args)
    set_opencv_threads(args)
    if config.mode != "online":
        raise InputError(None, "detect names the markings with the online tracker; --mode must be online")
    tripod, position = tripod_from_args(args)
    summary = export_detections(args.input, args.out, config, detector_options(args), tripod=tripod,
                                reinit_position=position, start=args.start, end=args.end,
                                write_masks=not args.no_masks, track_dir=args.track_out, progress=not args.no_progress)
    print(f"wrote {summary.records} of {summary.frames} frames to {summary.path} in {summary.seconds:.1f} s "
          f"({summary.frames_with_lines} with named lines, {summary.masks} masks"
          + (f" in {summary.mask_dir}" if summary.mask_dir else "") + f"), {warning_count()} warnings")
    return 0
