"""``broadtrack-graph evaluate``: the SoccerNet camera metric for a folder of camera files."""

from __future__ import annotations

import logging
from pathlib import Path

from broadtrack_graph.actions.evaluate import evaluate_folders, evaluation_table
from broadtrack_graph.arguments import int_at_least, positive_float
from broadtrack_graph.metrics.soccernet import DEFAULT_TAUS

log = logging.getLogger(__name__)

HELP = "score camera files against SoccerNet line annotations (JaC@tau, completeness, final score, MRE)"


def add_arguments(parser) -> None:
    parser.add_argument("--annotations", required=True, type=Path,
                        help="folder of per-image NNNNN.json annotations, or a Labels-GameState.json (or its folder)")
    parser.add_argument("--cameras", required=True, type=Path, help="folder of camera_NNNNN.json files, or a run folder (its cameras/ is used)")
    parser.add_argument("--width", type=int_at_least(2), default=960, help="evaluation width in pixels (default 960)")
    parser.add_argument("--height", type=int_at_least(2), default=540, help="evaluation height in pixels (default 540)")
    parser.add_argument("--tau", type=positive_float, nargs="+", default=list(DEFAULT_TAUS),
                        help=f"pixel threshold(s), several in one run (default {' '.join(f'{t:g}' for t in DEFAULT_TAUS)})")
    parser.add_argument("--json", type=Path, default=None, help="write the full report to this file")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bar")


def run(args) -> int:
    report = evaluate_folders(args.annotations, args.cameras, args.width, args.height, args.tau,
                              progress=not args.no_progress, json_path=args.json)
    for message in report["errors"].values():
        log.warning(message)
    if report["frames_with_camera"] == 0:
        log.warning("none of the %d annotated frames has a camera file in %s: check that the frame ids match",
                    report["frames"], report["cameras"])
    print(f"cameras read from {report.get('cameras', args.cameras)}")
    print(evaluation_table(report, args.width, args.height))
    if args.json is not None:
        print(f"report written to {args.json}")
    return 0
