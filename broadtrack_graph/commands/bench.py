"""``broadtrack-graph bench SUITE``: speed and accuracy benchmarks with JSON output."""

from __future__ import annotations

import importlib
import json
from pathlib import Path

from broadtrack_graph.actions.bench import run_benchmark

HELP = "run a benchmark suite and print / write its JSON report"

SUITES = (
    # one line per suite module in broadtrack_graph/benchmarks/
    "graph",
    "render",
    "frontend",
    "accuracy",
    "speed",
    "detections",
    "endurance",
    "real",
    "players",
    "scale",
    "broadcast",
    "model",
    "placements",
)


def add_arguments(parser) -> None:
    suites = parser.add_subparsers(dest="suite", required=True, metavar="SUITE")
    for name in SUITES:
        module = importlib.import_module(f"broadtrack_graph.benchmarks.{name}")
        sub = suites.add_parser(name, help=module.HELP, description=module.HELP)
        sub.add_argument("--json", type=Path, default=None, help="write the report to this file too")
        module.add_arguments(sub)
        sub.set_defaults(_suite_run=module.run)


def run(args) -> int:
    report = run_benchmark(args.suite, lambda: args._suite_run(args), args.json)
    print(json.dumps(report, indent=2, default=str))
    return 0
