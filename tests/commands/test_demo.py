"""``demo`` arguments -> DemoSettings and the demo action."""

from __future__ import annotations

from pathlib import Path

import broadtrack_graph.commands.demo as demo_command
from broadtrack_graph.actions.demo import DemoSettings
from broadtrack_graph.cli import main


def test_settings_reach_the_action(monkeypatch, capsys):
    seen = []

    def fake_run_demo(out, settings, progress):
        seen.append((out, settings, progress))
        return {"table": "| t |", "clip": "c", "runs": {"online": "o"}, "compare": "cmp", "overlay": None,
                "clip_reused": True, "disk_mb": 12.0, "clip_disk_mb": 10.0}

    monkeypatch.setattr(demo_command, "run_demo", fake_run_demo)
    monkeypatch.setattr("broadtrack_graph.cli._stderr_is_terminal", lambda: True)  # bars only show on a terminal
    assert main(["demo", "--no-progress"]) == 0
    assert seen[0] == (Path("runs/demo"), DemoSettings(), False)
    assert main(["demo", "--out", "d", "--frames", "30", "--width", "640", "--height", "360", "--seed", "4",
                 "--no-overlay"]) == 0
    assert seen[1] == (Path("d"), DemoSettings(frames=30, width_px=640, height_px=360, seed=4, overlay=False), True)
    assert "| t |" in capsys.readouterr().out
