"""shots.json round trip (broadtrack_graph.io.shots_file)."""

from __future__ import annotations

import pytest

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.shots_file import read_shots, write_shots
from broadtrack_graph.types.shot import Shot


def test_round_trip(tmp_path):
    shots = [Shot(0, 480, "main", "main", "start", {"main": 480}),
             Shot(480, 586, "close-up", None, "hard", {"close-up": 100, "main": 6})]
    write_shots(tmp_path / "shots.json", shots)
    assert read_shots(tmp_path / "shots.json") == shots


def test_bad_file_is_one_line_error(tmp_path):
    (tmp_path / "shots.json").write_text('{"shots": [{"start": 5, "end": 5, "kind": "main"}]}')
    with pytest.raises(InputError, match="end must be after start"):
        read_shots(tmp_path / "shots.json")
    (tmp_path / "shots.json").write_text('{"cuts": []}')
    with pytest.raises(InputError, match="expected"):
        read_shots(tmp_path / "shots.json")
