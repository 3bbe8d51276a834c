"""The comparison report: its Markdown table, and the files (compare.json, compare.md, plots).

The figures are :mod:`broadtrack_graph.metrics.compare`'s; this module only lays them out.
"""

from __future__ import annotations

import math
from pathlib import Path

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.jsonfile import write_json_atomic
from broadtrack_graph.metrics.compare import COMPARE_TAUS
from broadtrack_graph.types.track_record import RunRecords


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
    if any(s.get("players") for s in runs.values()):
        row("players: boxes located", lambda s: f"{s['players']['located']} / {s['players']['boxes']}")
        row("players: tracks", lambda s: str(s["players"]["tracks"]))
        row("players: total distance (m)", lambda s: _fmt(s["players"]["total_distance_m"], 1))
        row("players: median top speed (m/s)", lambda s: _fmt(s["players"]["median_top_speed_m_s"], 2))
        row("players: max top speed (m/s)", lambda s: _fmt(s["players"]["max_top_speed_m_s"], 2))
        row("players: median jitter RMS (m)", lambda s: _fmt(s["players"]["median_jitter_rms_m"], 3))
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


def write_comparison(report: dict, tracks: dict[str, RunRecords], truth: RunRecords | None, out_dir: str | Path) -> dict:
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
