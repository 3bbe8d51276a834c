"""Tests of io/frames.py: open_frames dispatches a path to the right frame source."""

from __future__ import annotations

import json

import pytest
from frame_files import write_folder, write_video

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.frames import open_frames
from broadtrack_graph.io.gamestate_sequence import GameStateSequenceSource
from broadtrack_graph.io.image_folder import ImageFolderSource
from broadtrack_graph.io.video import VideoSource


def test_open_frames_dispatches_by_path(tmp_path):
    write_folder(tmp_path / "images", 2)
    write_folder(tmp_path / "sequence" / "img1", 2)
    (tmp_path / "sequence" / "Labels-GameState.json").write_text(json.dumps({"info": {}}))
    write_video(tmp_path / "clip.mp4", 3)
    assert type(open_frames(tmp_path / "images")) is ImageFolderSource
    assert type(open_frames(tmp_path / "sequence")) is GameStateSequenceSource
    assert type(open_frames(tmp_path / "sequence" / "Labels-GameState.json")) is GameStateSequenceSource
    with open_frames(tmp_path / "clip.mp4") as video:
        assert type(video) is VideoSource
    assert open_frames(tmp_path / "images", fps=None).fps == 25.0


def test_bad_folders_raise_input_error_naming_the_path(tmp_path):
    with pytest.raises(InputError, match="not found") as info:
        open_frames(tmp_path / "nope")
    assert str(tmp_path / "nope") in str(info.value)
    empty = tmp_path / "empty"
    empty.mkdir()
    (empty / "notes.txt").write_text("x")
    with pytest.raises(InputError, match="no image files") as info:
        open_frames(empty)
    assert str(empty) in str(info.value)
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / "000001.jpg").write_bytes(b"junk")
    with pytest.raises(InputError, match="can be decoded"):
        open_frames(broken)
    write_folder(tmp_path / "ok", 3)
    with pytest.raises(InputError, match="past the end"):
        open_frames(tmp_path / "ok", start=3)
    with pytest.raises(InputError, match="greater than"):
        open_frames(tmp_path / "ok", start=2, end=2)
    with pytest.raises(InputError, match="single image"):
        open_frames(tmp_path / "ok" / "000001.jpg")
