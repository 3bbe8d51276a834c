"""``broadtrack-graph track-many``: one-line errors (no Ray, bad arguments, bad manifest) before any work."""

from __future__ import annotations

import sys

from broadtrack_graph.cli import main


def test_without_ray_it_says_how_to_install_it(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "ray", None)  # as if not installed
    (tmp_path / "a.jsonl").write_text('{"frame": 0}\n')
    assert main(["track-many", str(tmp_path / "a.jsonl"), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip()
    assert "pip install 'broadtrack-graph[scale]'" in err and len(err.splitlines()) == 1
    assert not (tmp_path / "out").exists()


def test_bad_arguments_and_manifests_are_one_line_errors(tmp_path, monkeypatch, capsys):
    import broadtrack_graph.actions.ray_engine as engine

    monkeypatch.setattr(engine, "require_ray", lambda: None)  # the checks below come before Ray starts
    (tmp_path / "a.jsonl").write_text('{"frame": 0}\n')
    manifest = tmp_path / "m.jsonl"
    manifest.write_text('{"detections": "missing.jsonl"}\n')
    for argv, problem in (
        ([str(tmp_path / "a.jsonl"), "--manifest", str(manifest)], "one of the two"),
        ([], "one of the two"),
        (["--manifest", str(manifest)], "line 1: detections"),
        ([str(tmp_path / "a.jsonl"), "--workers", "0"], "--workers must be >= 1"),
    ):
        assert main(["track-many", *argv, "--out", str(tmp_path / "out")]) == 2
        err = capsys.readouterr().err.strip()
        assert problem in err and len(err.splitlines()) == 1, err
