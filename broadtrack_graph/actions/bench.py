"""Run one benchmark suite and write its JSON report (the ``bench`` command)."""

from __future__ import annotations

import platform
import sys
import time
from collections.abc import Callable
from pathlib import Path

from broadtrack_graph.io.jsonfile import write_json_atomic


def run_benchmark(suite: str, run_suite: Callable[[], dict], json_path: str | Path | None = None) -> dict:
    """Run a suite and wrap its report with the machine and the wall time.

    Args:
        suite: the suite's name (stored as "suite").
        run_suite: runs the suite and returns its report (a JSON-ready dict).
        json_path: also write the report here (atomically).

    Returns:
        {"suite", "machine" {"python", "platform", "processor"}, "wall_time_s", **the suite's report}.
    """
    started = time.time()
    report = run_suite()
    report = {
        "suite": suite,
        "machine": {"python": sys.version.split()[0], "platform": platform.platform(), "processor": platform.processor()},
        "wall_time_s": round(time.time() - started, 3),
        **report,
    }
    if json_path is not None:
        write_json_atomic(json_path, report, indent=2)
    return report
