"""``detect`` arguments -> the detect actions: track's options (and --config), annotations import; bad input exits 2."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import pytest

import broadtrack_graph.actions.detect as detect_action
from broadtrack_graph.actions.track import DetectorOptions
from broadtrack_graph.cli import main
from broadtrack_graph.track.config import TrackingConfig


@pytest.fixture
def calls(monkeypatch):
    seen = []

    def fake_export(frames, out, config, detector, **kwargs):
        seen.append(("export", frames, out, config, detector, kwargs))
        return SimpleNamespace(records=2, frames=2, path=out, seconds=1.0, frames_with_lines=2, masks=0, mask_dir=None)

    def fake_import(source, out, width, height, first_number):
        seen.append(("import", source, out, width, height, first_number))
        return SimpleNamespace(records=4, path=out, skipped=[])

    monkeypatch.setattr(detect_action, "export_detections", fake_export)
    monkeypatch.setattr(detect_action, "import_annotations", fake_import)
    return seen


def test_frames_use_the_tracking_options(calls, tmp_path):
    config = tmp_path / "detect.toml"
    config.write_text("lag_frames = 9\n[flow]\nwindow_px = 21\n", encoding="utf-8")
    assert main(["detect", "clip", "--out", "d.jsonl", "--config", str(config), "--no-tripod", "--no-masks",
                 "--no-progress"]) == 0
    kind, frames, out, tracking, detector, kwargs = calls[0]
    assert (kind, frames, out, detector) == ("export", Path("clip"), Path("d.jsonl"), DetectorOptions())
    assert tracking.lag_frames == 9 and tracking.flow.window_px == 21 and tracking.use_tripod is False
    assert tracking.mode == TrackingConfig().mode
    assert kwargs["write_masks"] is False and kwargs["progress"] is False and kwargs["track_dir"] is None


def test_annotations_import(calls, capsys):
    assert main(["detect", "--annotations", "ann", "--out", "d.jsonl", "--width", "960", "--height", "540"]) == 0
    assert calls == [("import", Path("ann"), Path("d.jsonl"), 960, 540, None)]
    assert "imported 4 annotated frames" in capsys.readouterr().out


def test_mode_other_than_online_exits_2(calls, capsys, tmp_path):
    (tmp_path / "batch.toml").write_text('mode = "batch"\n', encoding="utf-8")
    assert main(["detect", "clip", "--out", "d.jsonl", "--config", str(tmp_path / "batch.toml")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--mode must be online" in err
    assert main(["detect", "--out", "d.jsonl"]) == 2 and "give either INPUT" in capsys.readouterr().err
    assert not calls
