"""The track-many manifest: JSON lines, one clip per line; bad manifests are one-line errors naming the line."""

from __future__ import annotations

import json

import pytest

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.manifest import clips_from_inputs, read_manifest, write_manifest


@pytest.fixture()
def files(tmp_path):
    (tmp_path / "a.jsonl").write_text('{"frame": 0}\n')
    (tmp_path / "frames").mkdir()
    (tmp_path / "tripod.json").write_text("{}")
    return tmp_path


def test_manifest_with_relative_paths_comments_and_options(files):
    path = files / "clips.jsonl"
    path.write_text("# a season\n\n"
                    + json.dumps({"detections": "a.jsonl", "mode": "batch", "chunk_frames": 500}) + "\n"
                    + json.dumps({"input": "frames", "name": "b", "tripod": "tripod.json", "start": 10, "end": 90}) + "\n")
    a, b = read_manifest(path)
    assert a.name == "a" and a.detections == files / "a.jsonl" and a.mode == "batch" and a.chunk_frames == 500
    assert a.input is None and a.start is None
    assert b.name == "b" and b.input == files / "frames" and b.tripod == files / "tripod.json"
    assert (b.start, b.end, b.mode) == (10, 90, None)


def test_write_then_read(files):
    path = write_manifest(files / "m" / "clips.jsonl", [{"detections": str(files / "a.jsonl"), "name": "x"}])
    assert [c.name for c in read_manifest(path)] == ["x"]


@pytest.mark.parametrize("line, problem", [
    ("{not json", "line 1: not valid JSON"),
    ("[1, 2]", "line 1: expected a JSON object"),
    ('{"input": "nowhere.mp4"}', "input"),
    ('{"name": "x"}', "needs 'input' or 'detections'"),
    ('{"detections": "a.jsonl", "colour": 1}', "unknown key(s) colour"),
    ('{"detections": "a.jsonl", "start": -1}', "'start' must be a non-negative integer"),
    ('{"detections": "a.jsonl", "start": 9, "end": 9}', "end 9 must be greater than start 9"),
    ('{"detections": "a.jsonl", "mode": "fast"}', "mode must be one of"),
    ('{"detections": "a.jsonl", "name": "../up"}', "plain folder name"),
    ('{"detections": "a.jsonl", "chunk_frames": 5}', "chunk_frames must be at least 20"),
    ('{"detections": "a.jsonl"}\n{"detections": "a.jsonl"}', "clip name 'a' appears twice"),
])
def test_bad_manifests_are_one_line_errors(files, line, problem):
    path = files / "bad.jsonl"
    path.write_text(line + "\n")
    with pytest.raises(InputError) as info:
        read_manifest(path)
    message = str(info.value)
    assert problem in message and "\n" not in message and "bad.jsonl" in message


def test_missing_and_empty_manifests(files):
    with pytest.raises(InputError, match="manifest not found"):
        read_manifest(files / "none.jsonl")
    (files / "empty.jsonl").write_text("# nothing\n")
    with pytest.raises(InputError, match="lists no clip"):
        read_manifest(files / "empty.jsonl")


def test_command_line_inputs(files):
    a, b = clips_from_inputs([files / "a.jsonl", files / "frames"])
    assert a.detections == files / "a.jsonl" and b.input == files / "frames" and b.name == "frames"
    with pytest.raises(InputError, match="appears twice"):
        clips_from_inputs([files / "a.jsonl", files / "a.jsonl"])
