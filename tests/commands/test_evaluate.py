"""``evaluate`` arguments -> the evaluate action; the printed table; bad values exit 2."""

from __future__ import annotations

from pathlib import Path

import broadtrack_graph.commands.evaluate as evaluate_command
from broadtrack_graph.cli import main
from broadtrack_graph.metrics.soccernet import DEFAULT_TAUS

REPORT = {"frames": 4, "frames_with_camera": 3, "errors": {"00002": "camera_00002.json: empty file"},
          "taus": {"5": {"final_score": 0.5, "completeness": 0.75, "accuracy": 0.6, "precision": 0.7, "recall": 0.8,
                         "mre_px": 1.234, "medre_px": None}}}


def test_arguments_reach_the_action(monkeypatch, capsys):
    seen = []
    monkeypatch.setattr(evaluate_command, "evaluate_folders", lambda *a, **k: seen.append((a, k)) or REPORT)
    assert main(["evaluate", "--annotations", "ann", "--cameras", "cams", "--json", "r.json", "--no-progress"]) == 0
    assert seen == [((Path("ann"), Path("cams"), 960, 540, list(DEFAULT_TAUS)), {"progress": False, "json_path": Path("r.json")})]
    captured = capsys.readouterr()
    out = captured.out.splitlines()
    assert captured.err == "WARNING broadtrack_graph.commands.evaluate: camera_00002.json: empty file\n"  # stderr, not stdout
    assert out[0] == "cameras read from cams"
    assert out[1] == "frames 4  with camera 3  resolution 960x540"
    assert out[3].split() == ["5", "0.5000", "0.7500", "0.6000", "0.7000", "0.8000", "1.23", "-"]
    assert out[4] == "report written to r.json"


def test_bad_resolution_exits_2_with_one_line(tmp_path, capsys):
    assert main(["evaluate", "--annotations", str(tmp_path), "--cameras", str(tmp_path), "--width", "1"]) == 2
    err = capsys.readouterr().err
    assert err == ("broadtrack-graph evaluate: error: argument --width: 1 is too small; give an integer >= 2 "
                   "(see broadtrack-graph evaluate --help)\n")


def test_a_run_folder_is_read_through_its_cameras_and_named(tmp_path, capsys):
    import json

    from broadtrack_graph.geometry.camera import Camera
    from broadtrack_graph.io.cameras import write_camera_file

    (tmp_path / "ann").mkdir()
    (tmp_path / "ann" / "00001.json").write_text(json.dumps({"Middle line": [{"x": 0.5, "y": 0.2}, {"x": 0.5, "y": 0.8}]}))
    write_camera_file(tmp_path / "run" / "cameras" / "camera_00001.json",
                      Camera(1500.0, 0.0, 0.0, 1.3, 0.0, (0.0, 55.0, -12.0), 960, 540))
    assert main(["evaluate", "--annotations", str(tmp_path / "ann"), "--cameras", str(tmp_path / "run"),
                 "--no-progress"]) == 0
    out = capsys.readouterr().out
    assert f"cameras read from {tmp_path / 'run' / 'cameras'}" in out and "with camera 1" in out
    (tmp_path / "empty").mkdir()
    assert main(["evaluate", "--annotations", str(tmp_path / "ann"), "--cameras", str(tmp_path / "empty")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no camera_<id>.json file in this folder" in err


def test_a_folder_of_unusable_annotations_names_the_first_bad_file(tmp_path, capsys):
    annotations = tmp_path / "ann"
    annotations.mkdir()
    (annotations / "00001.json").write_text("")
    (annotations / "00002.json").write_text("[1, 2]")
    cameras = tmp_path / "cams"
    cameras.mkdir()
    assert main(["evaluate", "--annotations", str(annotations), "--cameras", str(cameras), "--no-progress"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert "no usable annotation file (2 unreadable, the first:" in err[0] and "00001.json: empty file" in err[0]
