"""``broadtrack-graph bench SUITE``: speed and accuracy benchmarks with JSON output."""

from __future__ import annotations

import importlib
import json
import platform
import sys
import time
from pathlib import Path

from broadtrack_graph.io.jsonfile import write_json_atomic

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
    started = time.time()
    report = args._suite_run(args)
    report = {
        "suite": args.suite,
        "machine": {"python": sys.version.split()[0], "platform": platform.platform(), "processor": platform.processor()},
        "wall_time_s": round(time.time() - started, 3),
        **report,
    }
    text = json.dumps(report, indent=2, default=str)
    print(text)
    if args.json is not None:
        write_json_atomic(args.json, report, indent=2)
    return 0
