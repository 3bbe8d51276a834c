"""``players`` command: arguments reach the action; bad input exits 2 with one line."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.cli import main
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.io.track_writer import TrackWriter


def _run(tmp_path):
    run = tmp_path / "run"
    camera = Camera.from_degrees(2400.0, 0.0, 0.0, 74.0, 0.0, [0.0, 55.0, -15.0], 1920, 1080)
    from broadtrack_graph.types.track_record import TrackRecord

    with TrackWriter(run, 1920, 1080) as writer:
        writer.write(TrackRecord(0, "000001", 0.0, camera))
    u, v = camera.project(np.array([[3.0, 10.0, 0.0]]))[0][0]
    (tmp_path / "boxes.txt").write_text(f"1,5,{u - 10},{v - 40},20,40,1\n")
    return run


def test_players_command_writes_the_files(tmp_path, capsys):
    run = _run(tmp_path)
    assert main(["players", str(run), "--boxes", str(tmp_path / "boxes.txt"), "--out", str(tmp_path / "out"),
                 "--no-progress"]) == 0
    assert "1 of 1 boxes located" in capsys.readouterr().out
    for name in ("players.jsonl", "predictions-gamestate.json", "players_summary.json"):
        assert (tmp_path / "out" / name).is_file()


def test_missing_box_file_exits_2_with_one_line(tmp_path, capsys):
    run = _run(tmp_path)
    assert main(["players", str(run), "--boxes", str(tmp_path / "nope.txt"), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "nope.txt" in err
