"""``broadtrack-graph compare``: metric table, jitter and focal point spread of runs, with plots."""

from __future__ import annotations

import logging
from pathlib import Path

from broadtrack_graph.arguments import finite_float, int_at_least

log = logging.getLogger(__name__)

HELP = "compare camera runs (filter vs smoother, ...): JaC, MRE, completeness, jitter, focal point spread, plots"


def add_arguments(parser) -> None:
    parser.add_argument("runs", type=Path, nargs="+",
                        help="run folders (track.jsonl) or folders of camera_*.json files; usually two")
    parser.add_argument("--annotations", type=Path, default=None,
                        help="SoccerNet annotations: folder of NNNNN.json, a Labels-GameState.json or its folder")
    parser.add_argument("--ground-truth", type=Path, default=None,
                        help="folder of ground-truth camera files (or a run) for parameter errors")
    parser.add_argument("--names", nargs="+", default=None, help="a display name per run")
    parser.add_argument("--out", type=Path, default=None,
                        help="write compare.json, compare.md, series.png, focal_points.png here")
    parser.add_argument("--tripod-position", type=finite_float, nargs=3, default=None, metavar=("X", "Y", "Z"),
                        help="tripod point T (metres, pitch frame, z down) to mark on the focal point plot")
    parser.add_argument("--eval-size", type=int_at_least(2), nargs=2, default=None, metavar=("W", "H"),
                        help="evaluation resolution (default: the annotations' image size, else the run's)")


def run(args) -> int:
    from broadtrack_graph.actions.compare import compare_runs

    report = compare_runs(args.runs, args.names, args.annotations, args.ground_truth, args.out,
                          args.tripod_position, tuple(args.eval_size) if args.eval_size else None)
    print(report["table_markdown"])
    for name, stats in report["runs"].items():
        if stats.get("path"):
            print(f"run '{name}' read from {stats['path']}")
        metrics = stats.get("metrics")
        if metrics and metrics["frames_matched"] == 0:
            log.warning("run '%s': none of the %d annotated frame ids is in the run", name, metrics["frames_annotated"])
    if report.get("files"):
        print("\n".join(f"wrote {path}" for path in report["files"].values()))
    return 0
