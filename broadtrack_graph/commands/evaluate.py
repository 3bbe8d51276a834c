"""``broadtrack-graph evaluate``: the SoccerNet camera metric for a folder of camera files."""

from __future__ import annotations

import logging
from pathlib import Path

from broadtrack_graph.errors import InputError
from broadtrack_graph.metrics.soccernet import DEFAULT_TAUS, evaluate_cameras
from broadtrack_graph.io.annotations import read_annotations
from broadtrack_graph.io.cameras import list_camera_files, read_camera_file
from broadtrack_graph.io.jsonfile import write_json_atomic

HELP = "score camera files against SoccerNet line annotations (JaC@tau, completeness, final score, MRE)"
log = logging.getLogger(__name__)


def add_arguments(parser) -> None:
    parser.add_argument("--annotations", required=True, type=Path,
                        help="folder of per-image NNNNN.json annotations, or a Labels-GameState.json (or its folder)")
    parser.add_argument("--cameras", required=True, type=Path, help="folder of camera_NNNNN.json files")
    parser.add_argument("--width", type=int, default=960, help="evaluation width in pixels (default 960)")
    parser.add_argument("--height", type=int, default=540, help="evaluation height in pixels (default 540)")
    parser.add_argument("--tau", type=float, nargs="+", default=list(DEFAULT_TAUS),
                        help="pixel threshold(s), several in one run (default 5 10 20)")
    parser.add_argument("--json", type=Path, default=None, help="write the full report to this file")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")


def load_cameras(folder: Path, frame_ids, width_px: int, height_px: int):
    """Read the camera files of the given frames; a broken file counts as a missing camera.

    Returns:
        (cameras: frame id -> Camera | None, errors: frame id -> one-line message)
    """
    files = list_camera_files(folder)
    cameras, errors = {}, {}
    for frame_id in frame_ids:
        path = files.get(frame_id)
        if path is None:
            cameras[frame_id] = None
            continue
        try:
            cameras[frame_id] = read_camera_file(path, width_px, height_px)
        except InputError as exc:
            cameras[frame_id] = None
            errors[frame_id] = str(exc)
    return cameras, errors


def evaluate_folders(annotations_path: Path, cameras_path: Path, width_px: int, height_px: int, taus,
                     progress: bool = True) -> dict:
    """Read annotations and camera files and return the metric report."""
    if width_px < 2 or height_px < 2:
        raise InputError(None, f"evaluation resolution must be at least 2x2, got {width_px}x{height_px}")
    annotations = read_annotations(annotations_path)
    if not annotations.frames:
        raise InputError(annotations_path, "no usable annotation file")
    cameras, camera_errors = load_cameras(cameras_path, annotations.frames, width_px, height_px)
    report = evaluate_cameras(annotations, cameras, width_px, height_px, taus, camera_errors=camera_errors,
                              progress=progress)
    report["annotations"] = str(annotations_path)
    report["cameras"] = str(cameras_path)
    return report


def run(args) -> int:
    report = evaluate_folders(args.annotations, args.cameras, args.width, args.height, args.tau,
                              progress=not args.no_progress)
    for message in report["errors"].values():
        print(f"warning: {message}")
    print(f"frames {report['frames']}  with camera {report['frames_with_camera']}  "
          f"resolution {args.width}x{args.height}")
    print(f"{'tau px':>7} {'final':>8} {'complete':>9} {'accuracy':>9} {'precision':>10} {'recall':>8} "
          f"{'MRE px':>7} {'MedRE px':>9}")
    for key, row in report["taus"].items():
        mre = "-" if row["mre_px"] is None else f"{row['mre_px']:.2f}"
        medre = "-" if row["medre_px"] is None else f"{row['medre_px']:.2f}"
        print(f"{key:>7} {row['final_score']:8.4f} {row['completeness']:9.4f} {row['accuracy']:9.4f} "
              f"{row['precision']:10.4f} {row['recall']:8.4f} {mre:>7} {medre:>9}")
    if args.json is not None:
        write_json_atomic(args.json, report, indent=1)
        print(f"report written to {args.json}")
    return 0
