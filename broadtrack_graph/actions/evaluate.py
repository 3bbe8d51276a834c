"""Evaluate a folder of camera files against SoccerNet line annotations (the ``evaluate`` command).

:func:`evaluate_folders` reads both and returns the metric report of
:func:`broadtrack_graph.metrics.soccernet.evaluate_cameras`, written to JSON on request.
"""

from __future__ import annotations

from pathlib import Path

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.annotations import read_annotations
from broadtrack_graph.io.cameras import read_camera_file, resolve_camera_folder
from broadtrack_graph.io.jsonfile import write_json_atomic
from broadtrack_graph.metrics.soccernet import DEFAULT_TAUS, evaluate_cameras


def load_cameras(folder: Path, frame_ids, width_px: int, height_px: int):
    """Read the camera files of the given frames; a broken file counts as a missing camera.

    Args:
        folder: a folder of camera files or a run folder (its cameras/ is read).

    Returns:
        (cameras: frame id -> Camera | None, errors: frame id -> one-line message)

    Raises:
        InputError: the folder is missing or holds no camera file.
    """
    folder, files = resolve_camera_folder(folder)
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


def evaluate_folders(annotations_path: Path, cameras_path: Path, width_px: int, height_px: int, taus=DEFAULT_TAUS,
                     progress: bool = True, json_path: Path | None = None) -> dict:
    """Read annotations and camera files and return the metric report (also written to json_path when given).

    Raises:
        InputError: resolution below 2x2, a tau not > 0, no usable annotation, or the camera folder missing
            or without camera files (a run folder is accepted: its cameras/ is read; ``report["cameras"]``
            names the folder used).
    """
    if width_px < 2 or height_px < 2:
        raise InputError(None, f"evaluation resolution must be at least 2x2, got {width_px}x{height_px}")
    bad = [t for t in taus if not (float(t) > 0 and float(t) < float("inf"))]
    if bad:
        raise InputError(None, f"tau must be a finite number of pixels > 0, got {bad[0]}")
    annotations = read_annotations(annotations_path)
    if not annotations.frames:
        raise InputError(annotations_path, annotations.no_frames_reason())
    cameras_path, _ = resolve_camera_folder(cameras_path)
    cameras, camera_errors = load_cameras(cameras_path, annotations.frames, width_px, height_px)
    report = evaluate_cameras(annotations, cameras, width_px, height_px, taus, camera_errors=camera_errors,
                              progress=progress)
    report["annotations"] = str(annotations_path)
    report["cameras"] = str(cameras_path)
    if json_path is not None:
        write_json_atomic(json_path, report, indent=1)
    return report


def evaluation_table(report: dict, width_px: int, height_px: int) -> str:
    """The report as a text table: one row per tau (final score, completeness, accuracy, ..., MRE)."""
    lines = [f"frames {report['frames']}  with camera {report['frames_with_camera']}  resolution {width_px}x{height_px}",
             f"{'tau px':>7} {'final':>8} {'complete':>9} {'accuracy':>9} {'precision':>10} {'recall':>8} "
             f"{'MRE px':>7} {'MedRE px':>9}"]
    for key, row in report["taus"].items():
        mre = "-" if row["mre_px"] is None else f"{row['mre_px']:.2f}"
        medre = "-" if row["medre_px"] is None else f"{row['medre_px']:.2f}"
        lines.append(f"{key:>7} {row['final_score']:8.4f} {row['completeness']:9.4f} {row['accuracy']:9.4f} "
                     f"{row['precision']:10.4f} {row['recall']:8.4f} {mre:>7} {medre:>9}")
    return "\n".join(lines)
