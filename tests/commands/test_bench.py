"""``bench`` -> the bench action: the suite's report wrapped with machine and wall time, printed and written."""

from __future__ import annotations

import json

import broadtrack_graph.benchmarks.render as render_suite
from broadtrack_graph.cli import main


def test_suite_report_is_printed_and_written(monkeypatch, tmp_path, capsys):
    monkeypatch.setattr(render_suite, "run", lambda args: {"frames": args.frames, "value": 1.5})
    path = tmp_path / "bench.json"
    assert main(["bench", "render", "--frames", "3", "--json", str(path)]) == 0
    printed = json.loads(capsys.readouterr().out)
    written = json.loads(path.read_text())
    assert printed == written
    assert written["suite"] == "render" and written["frames"] == 3 and written["value"] == 1.5
    assert set(written["machine"]) == {"python", "platform", "processor"} and written["wall_time_s"] >= 0


def test_detections_plot_defaults_to_a_scratch_folder():
    from pathlib import Path

    from broadtrack_graph.cli import build_parser

    parser = build_parser()
    args = parser.parse_args(["bench", "detections", "--plot"])
    assert args.plot == Path("runs/bench-detections")  # never docs/images (tracked in the repository)
    assert parser.parse_args(["bench", "detections"]).plot is None
    assert parser.parse_args(["bench", "detections", "--plot", "/tmp/p"]).plot == Path("/tmp/p")
