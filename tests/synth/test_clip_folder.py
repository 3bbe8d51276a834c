"""synth --out: an earlier clip is replaced whole; a file or a foreign folder is refused with one line."""

from __future__ import annotations

import pytest

from broadtrack_graph.cli import main
from broadtrack_graph.errors import InputError
from broadtrack_graph.synth.clip_folder import prepare_clip_folder


def test_an_earlier_clip_is_replaced_whole(tmp_path):
    out = tmp_path / "clip"
    assert main(["synth", "--out", str(out), "--frames", "4", "--width", "64", "--height", "48", "--no-progress",
                 "--no-masks"]) == 0
    assert main(["synth", "--out", str(out), "--frames", "2", "--width", "64", "--height", "48", "--no-progress",
                 "--no-masks"]) == 0
    assert len(list((out / "img1").iterdir())) == 2 and len(list((out / "cameras").iterdir())) == 2


def test_out_that_is_a_file_is_one_line_error(tmp_path, capsys):
    (tmp_path / "clip").write_text("x", encoding="utf-8")
    assert main(["synth", "--out", str(tmp_path / "clip"), "--frames", "2", "--width", "64", "--height", "48"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "exists and is not a folder" in err and "Traceback" not in err


def test_a_foreign_folder_is_refused_and_left_alone(tmp_path):
    (tmp_path / "mine.txt").write_text("keep", encoding="utf-8")
    with pytest.raises(InputError, match="holds mine.txt"):
        prepare_clip_folder(tmp_path)
    assert (tmp_path / "mine.txt").read_text() == "keep"
    assert prepare_clip_folder(tmp_path / "new") == 0
