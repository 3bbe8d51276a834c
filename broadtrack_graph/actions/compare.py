"""Compare runs: read them, compute the figures, write compare.json, compare.md and the plots.

The figures are :mod:`broadtrack_graph.metrics.compare`'s, the table and files
:mod:`broadtrack_graph.products.compare_report`'s.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.players_file import PLAYERS_FILE, read_players_file
from broadtrack_graph.io.run_folder import read_track
from broadtrack_graph.metrics.compare import COMPARE_TAUS, DEFINITIONS, compare_tracks, tripod_from_summary
from broadtrack_graph.metrics.players import fps_from_times
from broadtrack_graph.products.compare_report import format_table, write_comparison


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
        tripod_T_w: (3,) tripod point for the focal point plot, metres (default: the first
            run whose summary.json has ``"tripod": {"T_w": [x, y, z], ...}``).
        eval_size_px: (W, H) evaluation resolution (default: the annotations' image
            size when the file states it, else each run's own resolution).
        taus: metric thresholds, pixels.

    A run folder holding a ``players.jsonl`` (``track --players`` or ``players --out RUN``)
    adds its players' figures (distance covered, top speed, jitter) to the table.

    Returns:
        The report (as written to compare.json): "runs" name -> figures, "taus",
        "definitions", "table_markdown", "files".

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
    players, fps = {}, {}
    for name, path in zip(names, run_dirs):
        if (Path(path) / PLAYERS_FILE).is_file():
            players[name] = read_players_file(Path(path) / PLAYERS_FILE)
            times = np.array([np.nan if r.time_s is None else r.time_s for r in tracks[name].records], dtype=float)
            fps[name] = fps_from_times(times, tracks[name].frame_indices)
    report = compare_tracks(tracks, truth, annotations, eval_size_px, taus, players, fps)
    report["annotations"] = None if annotations_path is None else str(annotations_path)
    report["ground_truth"] = None if ground_truth_dir is None else str(ground_truth_dir)
    if tripod_T_w is None:
        tripod_T_w = next((t for t in map(tripod_from_summary, tracks.values()) if t is not None), None)
    report["tripod_T_w"] = None if tripod_T_w is None else [float(v) for v in np.asarray(tripod_T_w).reshape(3)]
    report["definitions"] = dict(DEFINITIONS)
    report["table_markdown"] = format_table(report)
    if out_dir is not None:
        report["files"] = write_comparison(report, tracks, truth, out_dir)
    return report


def _default_names(run_dirs) -> list[str]:
    names = []
    for path in run_dirs:
        base = Path(path).resolve().name or str(path)
        name, k = base, 2
        while name in names:
            name, k = f"{base}-{k}", k + 1
        names.append(name)
    return names
