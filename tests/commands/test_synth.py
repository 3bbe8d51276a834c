"""``synth`` arguments -> the clip writer; bad sizes exit 2 with one line."""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import broadtrack_graph.synth.writer as synth_writer
from broadtrack_graph.cli import main


def test_arguments_reach_the_writer(monkeypatch, capsys):
    seen = []

    def fake_write(out, **kwargs):
        seen.append((out, kwargs))
        return SimpleNamespace(frames_written=2, out_dir=out, seconds=1.0, seconds_per_frame=0.5)

    monkeypatch.setattr(synth_writer, "write_synthetic_clip", fake_write)
    assert main(["synth", "--out", "clip", "--frames", "2", "--width", "64", "--height", "48", "--preset", "16m",
                 "--seed", "3", "--mp4", "--no-masks", "--no-progress"]) == 0
    assert seen == [(Path("clip"), {"preset": "16m", "frame_count": 2, "width_px": 64, "height_px": 48, "seed": 3,
                                    "cameras_dir": None, "jpeg_quality": 90, "write_mp4": True, "write_masks": False,
                                    "progress": False})]
    assert "wrote 2 frames of 64x48" in capsys.readouterr().out


def test_bad_size_exits_2_with_one_line(capsys):
    assert main(["synth", "--out", "clip", "--width", "8"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "argument --width: 8 px is not a usable image side; give 16 .. 16384" in err
