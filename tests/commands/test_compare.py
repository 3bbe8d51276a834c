"""``compare`` arguments -> the compare action; bad input exits 2."""

from __future__ import annotations

from pathlib import Path

import broadtrack_graph.actions.compare as compare_action
from broadtrack_graph.cli import main


def test_arguments_reach_the_action(monkeypatch, capsys):
    seen = []

    def fake_compare_runs(*args):
        seen.append(args)
        return {"table_markdown": "| metric |", "runs": {"a": {"metrics": {"frames_matched": 0, "frames_annotated": 5}}},
                "files": {"json": "cmp/compare.json"}}

    monkeypatch.setattr(compare_action, "compare_runs", fake_compare_runs)
    assert main(["compare", "r1", "r2", "--names", "a", "b", "--annotations", "ann", "--out", "cmp",
                 "--tripod-position", "0", "55", "-12", "--eval-size", "960", "540"]) == 0
    assert seen == [([Path("r1"), Path("r2")], ["a", "b"], Path("ann"), None, Path("cmp"), [0.0, 55.0, -12.0], (960, 540))]
    captured = capsys.readouterr()
    assert "| metric |" in captured.out and "wrote cmp/compare.json" in captured.out
    assert "none of the 5 annotated frame ids" in captured.err  # warnings go to stderr


def test_missing_run_exits_2_with_one_line(tmp_path, capsys):
    assert main(["compare", str(tmp_path / "nope")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.endswith("nope: run folder not found\n")
