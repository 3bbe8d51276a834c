"""Compare camera tracks (filter vs smoother, or any runs): metrics, jitter, focal point spread, plots.

Figures per run (all computed over the frames that have a camera):

* SoccerNet metric when annotations are given (JaC@5, JaC@10 = accuracy at tau,
  completeness, final score, MRE / MedRE at tau 5), from :mod:`broadtrack_graph.metrics.soccernet`.
* Jitter of pan, tilt (deg) and focal length (px): the RMS of the first
  difference ``x[t] - x[t-1]`` (per frame; includes the real motion) and the RMS of
  the second difference ``x[t+1] - 2 x[t] + x[t-1]`` (per frame^2; real broadcast
  motion is smooth, so this is mostly noise). Only runs of consecutive frame
  indices with a camera count; pan differences are wrapped to (-180, 180].
* Spread of the focal point C: standard deviation per axis (population, ddof 0),
  extent (max - min) per axis, and RMS distance to the mean position, metres.
* Error against ground-truth cameras when given: RMS of pan / tilt / roll errors
  (deg), mean absolute relative focal error (%), RMS position error (m).

:func:`compare_runs` reads the runs and writes compare.json, compare.md and the plots.
"""

from __future__ import annotations

import logging
import math
from pathlib import Path

import numpy as np

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.jsonfile import write_json_atomic
from broadtrack_graph.io.run_folder import Track, read_track

logger = logging.getLogger(__name__)

COMPARE_TAUS = (5.0, 10.0)


# --------------------------------------------------------------------------- numbers


def _consecutive_differences(values: np.ndarray, frame_indices: np.ndarray, wrap_deg: bool) -> tuple[np.ndarray, np.ndarray]:
    values = np.asarray(values, dtype=float)
    frames = np.asarray(frame_indices, dtype=float)
    order = np.argsort(frames, kind="stable")
    values, frames = values[order], frames[order]
    d1 = np.diff(values)
    if wrap_deg:
        d1 = (d1 + 180.0) % 360.0 - 180.0
    step_ok = np.diff(frames) == 1
    first_ok = step_ok & np.isfinite(d1)
    d2 = d1[1:] - d1[:-1]
    second_ok = first_ok[1:] & first_ok[:-1]
    return d1[first_ok], d2[second_ok]


def jitter(values: np.ndarray, frame_indices: np.ndarray, wrap_deg: bool = False) -> dict:
    """RMS of the first and second differences of a per-frame series.

    Args:
        values: (N,) the series (NaN where a frame has no camera).
        frame_indices: (N,) frame index of each value; only steps of exactly 1 count.
        wrap_deg: wrap first differences to (-180, 180] (for pan in degrees).

    Returns:
        {"rms_d1": RMS(x[t] - x[t-1]), "rms_d2": RMS(x[t+1] - 2 x[t] + x[t-1]),
         "pairs": number of first differences, "triples": number of second differences};
        None values when there are no pairs / triples.
    """
    d1, d2 = _consecutive_differences(values, frame_indices, wrap_deg)
    return {
        "rms_d1": float(np.sqrt(np.mean(d1**2))) if len(d1) else None,
        "rms_d2": float(np.sqrt(np.mean(d2**2))) if len(d2) else None,
        "pairs": int(len(d1)),
        "triples": int(len(d2)),
    }


def focal_point_spread(positions_m: np.ndarray) -> dict:
    """Spread of focal point positions.

    Args:
        positions_m: (N, 3) C per frame, metres (NaN rows are ignored).

    Returns:
        {"frames", "mean_m" (3,), "std_m" (3,) population std per axis, "extent_m" (3,)
        max - min per axis, "rms_to_mean_m"}; None values without frames.
    """
    positions = np.asarray(positions_m, dtype=float).reshape(-1, 3)
    positions = positions[np.all(np.isfinite(positions), axis=1)]
    if not len(positions):
        return {"frames": 0, "mean_m": None, "std_m": None, "extent_m": None, "rms_to_mean_m": None}
    mean = positions.mean(axis=0)
    return {
        "frames": int(len(positions)),
        "mean_m": mean.tolist(),
        "std_m": positions.std(axis=0).tolist(),
        "extent_m": (positions.max(axis=0) - positions.min(axis=0)).tolist(),
        "rms_to_mean_m": float(np.sqrt(np.mean(np.sum((positions - mean) ** 2, axis=1)))),
    }


def track_statistics(track: Track) -> dict:
    """Jitter, focal point spread and counts of one track (see the module docstring)."""
    states = track.states()
    frames = track.frame_indices
    confidences = track.confidences()
    with_camera = int(np.isfinite(states[:, 0]).sum())
    return {
        "path": str(track.path),
        "resolution": [track.width_px, track.height_px],
        "frames": len(track),
        "frames_with_camera": with_camera,
        "share_with_camera": with_camera / len(track) if len(track) else None,
        "reinitialisations": int(sum(r.reinitialised for r in track.records)),
        "mean_confidence": float(np.nanmean(confidences)) if np.isfinite(confidences).any() else None,
        "jitter": {
            "pan_deg": jitter(states[:, 2], frames, wrap_deg=True),
            "tilt_deg": jitter(states[:, 3], frames),
            "focal_px": jitter(states[:, 0], frames),
        },
        "focal_point": focal_point_spread(states[:, 5:8]),
    }


def ground_truth_errors(track: Track, truth: Track) -> dict:
    """Camera parameter errors against ground truth, over frame ids present in both with cameras.

    Returns:
        {"frames", "pan_rms_deg", "tilt_rms_deg", "roll_rms_deg", "focal_mean_abs_rel_pct",
        "position_rms_m"} (None values when no frame matches).
    """
    truth_by_id = truth.cameras
    pairs = [
        (record.camera, truth_by_id[record.frame_id])
        for record in track.records
        if record.camera is not None and truth_by_id.get(record.frame_id) is not None
    ]
    if not pairs:
        return {"frames": 0, "pan_rms_deg": None, "tilt_rms_deg": None, "roll_rms_deg": None,
                "focal_mean_abs_rel_pct": None, "position_rms_m": None}
    est = np.array([[c.pan_deg, c.tilt_deg, c.roll_deg, c.focal_px / c.width_px, *c.position_m] for c, _ in pairs])
    ref = np.array([[c.pan_deg, c.tilt_deg, c.roll_deg, c.focal_px / c.width_px, *c.position_m] for _, c in pairs])
    error = est - ref
    error[:, 0] = (error[:, 0] + 180.0) % 360.0 - 180.0
    rms = np.sqrt(np.mean(error**2, axis=0))
    return {
        "frames": len(pairs),
        "pan_rms_deg": float(rms[0]),
        "tilt_rms_deg": float(rms[1]),
        "roll_rms_deg": float(rms[2]),
        "focal_mean_abs_rel_pct": float(100 * np.mean(np.abs(error[:, 3]) / ref[:, 3])),
        "position_rms_m": float(np.sqrt(np.mean(np.sum(error[:, 4:7] ** 2, axis=1)))),
    }


def metric_summary(annotations, track: Track, width_px: int, height_px: int, taus=COMPARE_TAUS) -> dict:
    """The SoccerNet metric of one track on the annotated frames (JaC per tau, completeness, MRE).

    Returns:
        {"frames_annotated", "frames_matched" (annotated ids present in the track),
        "frames_with_camera", "completeness", "jac" {tau: accuracy}, "final_score" {tau: ...},
        "mre_px", "medre_px" (at the first tau), "resolution"}.
    """
    from broadtrack_graph.metrics.soccernet import evaluate_cameras

    cameras = track.cameras
    matched = sum(1 for frame_id in annotations.frames if frame_id in cameras)
    if annotations.frames and not matched:
        logger.warning("%s: no annotated frame id is in the track (ids like %s vs %s)", track.path,
                       next(iter(annotations.frames)), next(iter(cameras), None))
    report = evaluate_cameras(annotations, cameras, width_px, height_px, taus)
    first = f"{taus[0]:g}"
    return {
        "frames_annotated": report["frames"],
        "frames_matched": matched,
        "frames_with_camera": report["frames_with_camera"],
        "completeness": report["completeness"],
        "jac": {key: row["accuracy"] for key, row in report["taus"].items()},
        "final_score": {key: row["final_score"] for key, row in report["taus"].items()},
        "mre_px": report["taus"][first]["mre_px"],
        "medre_px": report["taus"][first]["medre_px"],
        "resolution": [int(width_px), int(height_px)],
    }


# --------------------------------------------------------------------------- table


def _fmt(value, digits: int = 3, scale: float = 1.0, suffix: str = "") -> str:
    if value is None or (isinstance(value, float) and not math.isfinite(value)):
        return "-"
    return f"{value * scale:.{digits}f}{suffix}"


def comparison_rows(report: dict) -> list[tuple[str, list[str]]]:
    """(row label, one cell per run) for the comparison table."""
    runs = report["runs"]
    rows: list[tuple[str, list[str]]] = []

    def row(label, getter):
        cells = []
        for stats in runs.values():
            try:
                cells.append(getter(stats))
            except (KeyError, TypeError):
                cells.append("-")
        rows.append((label, cells))

    row("frames / with camera", lambda s: f"{s['frames']} / {s['frames_with_camera']}")
    row("re-initialisations", lambda s: str(s["reinitialisations"]))
    row("mean confidence", lambda s: _fmt(s["mean_confidence"]))
    if any(s.get("metrics") for s in runs.values()):
        for tau in report.get("taus", COMPARE_TAUS):
            key = f"{tau:g}"
            row(f"JaC@{key} (%)", lambda s, k=key: _fmt(s["metrics"]["jac"][k], 2, 100))
        row("completeness (%)", lambda s: _fmt(s["metrics"]["completeness"], 2, 100))
        row(f"final score@{report.get('taus', COMPARE_TAUS)[0]:g} (%)",
            lambda s: _fmt(s["metrics"]["final_score"][f"{report.get('taus', COMPARE_TAUS)[0]:g}"], 2, 100))
        row("MRE (px)", lambda s: _fmt(s["metrics"]["mre_px"], 2))
        row("MedRE (px)", lambda s: _fmt(s["metrics"]["medre_px"], 2))
        row("annotated frames matched", lambda s: f"{s['metrics']['frames_matched']} / {s['metrics']['frames_annotated']}")
    for name, unit, digits in (("pan_deg", "deg", 4), ("tilt_deg", "deg", 4), ("focal_px", "px", 2)):
        label = name.split("_")[0]
        row(f"{label} jitter RMS d1 ({unit}/frame)", lambda s, n=name, d=digits: _fmt(s["jitter"][n]["rms_d1"], d))
        row(f"{label} jitter RMS d2 ({unit}/frame^2)", lambda s, n=name, d=digits: _fmt(s["jitter"][n]["rms_d2"], d))
    for axis, index in (("x", 0), ("y", 1), ("z", 2)):
        row(f"C std {axis} (m)", lambda s, i=index: _fmt(s["focal_point"]["std_m"][i], 3))
    for axis, index in (("x", 0), ("y", 1), ("z", 2)):
        row(f"C extent {axis} (m)", lambda s, i=index: _fmt(s["focal_point"]["extent_m"][i], 3))
    row("C RMS to mean (m)", lambda s: _fmt(s["focal_point"]["rms_to_mean_m"], 3))
    if any(s.get("ground_truth_error") for s in runs.values()):
        row("GT pan error RMS (deg)", lambda s: _fmt(s["ground_truth_error"]["pan_rms_deg"], 4))
        row("GT tilt error RMS (deg)", lambda s: _fmt(s["ground_truth_error"]["tilt_rms_deg"], 4))
        row("GT roll error RMS (deg)", lambda s: _fmt(s["ground_truth_error"]["roll_rms_deg"], 4))
        row("GT focal error mean |rel| (%)", lambda s: _fmt(s["ground_truth_error"]["focal_mean_abs_rel_pct"], 3))
        row("GT position error RMS (m)", lambda s: _fmt(s["ground_truth_error"]["position_rms_m"], 3))
    return rows


def format_table(report: dict) -> str:
    """The comparison as a Markdown table (one column per run)."""
    names = list(report["runs"])
    rows = comparison_rows(report)
    label_w = max(len("metric"), *(len(label) for label, _ in rows))
    col_w = [max(len(name), *(len(cells[i]) for _, cells in rows)) for i, name in enumerate(names)]
    lines = [
        "| " + "metric".ljust(label_w) + " | " + " | ".join(n.rjust(w) for n, w in zip(names, col_w)) + " |",
        "|-" + "-" * label_w + "-|" + "|".join("-" * (w + 1) + ":" for w in col_w) + "|",
    ]
    for label, cells in rows:
        lines.append("| " + label.ljust(label_w) + " | " + " | ".join(c.rjust(w) for c, w in zip(cells, col_w)) + " |")
    return "\n".join(lines)


# --------------------------------------------------------------------------- the whole comparison


def _tripod_from_summary(track: Track):
    tripod = track.summary.get("tripod") if isinstance(track.summary, dict) else None
    if isinstance(tripod, dict) and isinstance(tripod.get("T_w"), list) and len(tripod["T_w"]) == 3:
        return np.asarray(tripod["T_w"], dtype=float)
    return None


def compare_runs(
    run_dirs: list[str | Path],
    names: list[str] | None = None,
    annotations_path: str | Path | None = None,
    ground_truth_dir: str | Path | None = None,
    out_dir: str | Path | None = None,
    tripod_T_w=None,
    eval_size_px: tuple[int, int] | None = None,
    taus=COMPARE_TAUS,
) -> dict:
    """Compare runs and, with ``out_dir``, write compare.json, compare.md, series.png and focal_points.png.

    Args:
        run_dirs: run folders (track.jsonl) or folders of camera files, at least one.
        names: a display name per run (default: the folder names, made unique).
        annotations_path: SoccerNet annotations (folder of NNNNN.json, a
            Labels-GameState.json or its folder) for the metric table.
        ground_truth_dir: a folder of ground-truth camera files (or a run) for
            parameter errors and the dashed line in the plots.
        out_dir: where to write the report and plots (None: nothing written).
        tripod_T_w: (3,) tripod point for the focal point plot (default: the first
            run whose summary.json has ``"tripod": {"T_w": [x, y, z], ...}``).
        eval_size_px: (W, H) evaluation resolution (default: the annotations' image
            size when the file states it, else each run's own resolution).
        taus: metric thresholds, pixels.

    Returns:
        The report (as written to compare.json): "runs" name -> figures, "taus",
        "definitions", "files".

    Raises:
        InputError: a run, the annotations or the ground truth cannot be read.
    """
    if not run_dirs:
        raise InputError(None, "compare needs at least one run folder")
    names = list(names) if names else _default_names(run_dirs)
    if len(names) != len(run_dirs):
        raise InputError(None, f"--names gives {len(names)} names for {len(run_dirs)} runs")
    if len(set(names)) != len(names):
        raise InputError(None, f"run names must differ, got {names}")
    tracks = {name: read_track(path) for name, path in zip(names, run_dirs)}
    truth = read_track(ground_truth_dir) if ground_truth_dir is not None else None
    annotations = None
    if annotations_path is not None:
        from broadtrack_graph.io.annotations import read_annotations

        annotations = read_annotations(annotations_path)
        if not annotations.frames:
            raise InputError(annotations_path, "no usable annotation")
    report: dict = {"runs": {}, "taus": [float(t) for t in taus]}
    for name, track in tracks.items():
        stats = track_statistics(track)
        if annotations is not None:
            size = eval_size_px or _annotation_size(annotations) or (track.width_px, track.height_px)
            stats["metrics"] = metric_summary(annotations, track, size[0], size[1], taus)
        if truth is not None:
            stats["ground_truth_error"] = ground_truth_errors(track, truth)
        report["runs"][name] = stats
    report["annotations"] = None if annotations_path is None else str(annotations_path)
    report["ground_truth"] = None if ground_truth_dir is None else str(ground_truth_dir)
    if tripod_T_w is None:
        tripod_T_w = next((t for t in map(_tripod_from_summary, tracks.values()) if t is not None), None)
    report["tripod_T_w"] = None if tripod_T_w is None else [float(v) for v in np.asarray(tripod_T_w).reshape(3)]
    report["definitions"] = {
        "jitter rms_d1": "RMS over consecutive frames of x[t] - x[t-1] (deg or px per frame)",
        "jitter rms_d2": "RMS over consecutive frames of x[t+1] - 2 x[t] + x[t-1] (deg or px per frame^2)",
        "focal_point std_m": "population standard deviation of C per axis (metres)",
        "focal_point extent_m": "max - min of C per axis (metres)",
        "JaC@tau": "SoccerNet accuracy at tau px: mean per-frame Jaccard over annotated frames with a camera",
        "MRE/MedRE": "mean / median distance of annotated points to their projected class, at the first tau",
    }
    report["table_markdown"] = format_table(report)
    if out_dir is not None:
        report["files"] = write_comparison(report, tracks, truth, out_dir)
    return report


def _annotation_size(annotations) -> tuple[int, int] | None:
    sizes = set(annotations.image_sizes.values())
    return next(iter(sizes)) if len(sizes) == 1 else None


def _default_names(run_dirs) -> list[str]:
    names = []
    for path in run_dirs:
        base = Path(path).resolve().name or str(path)
        name, k = base, 2
        while name in names:
            name, k = f"{base}-{k}", k + 1
        names.append(name)
    return names


def write_comparison(report: dict, tracks: dict[str, Track], truth: Track | None, out_dir: str | Path) -> dict:
    """Write compare.json, compare.md, series.png, focal_points.png into out_dir; returns their paths."""
    from broadtrack_graph.products.plots import plot_focal_points, plot_track_series

    out_dir = Path(out_dir)
    try:
        out_dir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise InputError(out_dir, f"cannot create output folder: {exc.strerror or exc}") from None
    files = {
        "json": str(out_dir / "compare.json"),
        "markdown": str(out_dir / "compare.md"),
        "series_png": str(out_dir / "series.png"),
        "focal_points_png": str(out_dir / "focal_points.png"),
    }
    title = " vs ".join(tracks)
    plot_track_series(tracks, files["series_png"], ground_truth=truth, title=f"{title}: camera parameters over time")
    plot_focal_points(tracks, files["focal_points_png"], report.get("tripod_T_w"), truth, title=f"{title}: focal points")
    lines = [f"# Comparison: {title}", ""]
    for name, stats in report["runs"].items():
        lines.append(f"- **{name}**: `{stats['path']}` ({stats['resolution'][0]}x{stats['resolution'][1]})")
    if report.get("annotations"):
        lines.append(f"- annotations: `{report['annotations']}`")
    if report.get("ground_truth"):
        lines.append(f"- ground truth cameras: `{report['ground_truth']}`")
    lines += ["", report["table_markdown"], "", "Definitions:", ""]
    lines += [f"- {key}: {text}" for key, text in report["definitions"].items()]
    lines += ["", "![parameters over time](series.png)", "", "![focal points](focal_points.png)", ""]
    Path(files["markdown"]).write_text("\n".join(lines), encoding="utf-8")
    write_json_atomic(files["json"], {**report, "files": files}, indent=2)
    return files
