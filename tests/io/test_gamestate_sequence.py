"""Tests of io/gamestate_sequence.py: SoccerNet game-state sequence folders."""

from __future__ import annotations

import json

import pytest
from frame_files import write_folder

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.frames import open_frames
from broadtrack_graph.io.gamestate_sequence import GameStateSequenceSource


def test_gamestate_sequence_folder(tmp_path):
    sequence = tmp_path / "SNGS-001"
    write_folder(sequence / "img1", 4)
    labels = {"info": {"frame_rate": 10, "im_dir": "img1"}, "images": [], "annotations": []}
    (sequence / "Labels-GameState.json").write_text(json.dumps(labels))
    for path in (sequence, sequence / "Labels-GameState.json"):
        source = open_frames(path, start=1)
        assert isinstance(source, GameStateSequenceSource)
        assert source.fps == 10.0 and source.labels_path == sequence / "Labels-GameState.json"
        frames = list(source)
        assert [f.frame_id for f in frames] == ["000002", "000003", "000004"]
        assert frames[0].time_s == pytest.approx(0.1)
    with pytest.raises(InputError, match="img1"):
        GameStateSequenceSource(tmp_path)


# --------------------------------------------------------------------------- videos
