"""``overlay`` arguments -> the overlay writer; a missing run exits 2 with one line."""

from __future__ import annotations

from pathlib import Path

import broadtrack_graph.products.overlay as overlay_product
from broadtrack_graph.cli import main


def test_arguments_reach_the_writer(monkeypatch, capsys):
    seen = []

    def fake_write_overlay(*args, **kwargs):
        seen.append((args, kwargs))
        return {"out": "o.mp4", "frames": 3, "with_camera": 2, "missing_input": 1}

    monkeypatch.setattr(overlay_product, "write_overlay", fake_write_overlay)
    assert main(["overlay", "run", "--frames", "clip", "--out", "o.mp4", "--start", "2", "--end", "5", "--no-inset",
                 "--no-progress"]) == 0
    assert seen == [((Path("run"), Path("clip"), Path("o.mp4"), 2, 5), {"inset": False, "progress": False, "players_path": None})]
    assert "wrote 3 frames to o.mp4 (2 with a camera, 1 unreadable input frames)" in capsys.readouterr().out


def test_missing_run_exits_2(tmp_path, capsys):
    assert main(["overlay", str(tmp_path / "nope"), "--frames", str(tmp_path), "--out", str(tmp_path / "o.mp4")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "run folder not found" in err
