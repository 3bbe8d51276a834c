"""``broadtrack-graph calibrate``: one camera per annotated frame from its labelled line points."""

from __future__ import annotations

import json
from pathlib import Path

from broadtrack_graph.errors import InputError
from broadtrack_graph.reinit.calibrate import FrameCalibration, calibrate_annotation_set, draw_calibration
from broadtrack_graph.io.annotations import read_annotations
from broadtrack_graph.io.cameras import camera_file_name, write_camera_file

HELP = "single-frame calibration: treat each annotation file's line points as detections, write camera files"


def add_arguments(parser) -> None:
    parser.add_argument("--annotations", required=True, type=Path,
                        help="folder of per-image NNNNN.json annotations, or a Labels-GameState.json (or its folder)")
    parser.add_argument("--out", required=True, type=Path, help="folder for camera_NNNNN.json files (created)")
    parser.add_argument("--width", type=int, default=960, help="image width in pixels the cameras are for (default 960)")
    parser.add_argument("--height", type=int, default=540, help="image height in pixels (default 540)")
    parser.add_argument("--jobs", type=int, default=1, help="worker processes (default 1)")
    parser.add_argument("--preview", type=Path, default=None,
                        help="write a PNG mosaic of 9 evenly spaced frames: template, points within 5 px green, others red")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")


def run(args) -> int:
    if args.width < 2 or args.height < 2:
        raise InputError(None, f"resolution must be at least 2x2, got {args.width}x{args.height}")
    annotations = read_annotations(args.annotations)
    if not annotations.frames:
        raise InputError(args.annotations, "no usable annotation file")
    args.out.mkdir(parents=True, exist_ok=True)

    frame_ids = sorted(annotations.frames)
    preview_ids = set(frame_ids[:: max(1, len(frame_ids) // 9)][:9])
    previews = []

    def write(result: FrameCalibration) -> None:
        if result.camera is not None:
            write_camera_file(args.out / camera_file_name(result.frame_id), result.camera, args.width, args.height)
        if args.preview is not None and result.frame_id in preview_ids:
            previews.append(draw_calibration(annotations.frames[result.frame_id], result.camera, args.width,
                                             args.height, title=result.frame_id))

    summary = calibrate_annotation_set(annotations, args.width, args.height, on_result=write, jobs=args.jobs,
                                       progress=not args.no_progress)
    summary["unreadable_annotations"] = annotations.errors
    if args.preview is not None and previews:
        import cv2
        import numpy as np

        previews += [np.zeros_like(previews[0])] * (-len(previews) % 3)
        rows = [np.hstack(previews[i:i + 3]) for i in range(0, len(previews), 3)]
        args.preview.parent.mkdir(parents=True, exist_ok=True)
        mosaic = np.vstack(rows)
        cv2.imwrite(str(args.preview), cv2.resize(mosaic, (mosaic.shape[1] // 2, mosaic.shape[0] // 2),
                                                  interpolation=cv2.INTER_AREA))
    missing = summary.pop("missing")
    print(json.dumps({**summary, "missing_count": len(missing), "missing": dict(list(missing.items())[:20])}, indent=2))
    return 0
