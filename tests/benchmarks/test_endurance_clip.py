"""Tests of benchmarks/endurance_clip.py: the ping-pong frame order and the linked clip folder."""

from __future__ import annotations

import numpy as np
import pytest

from broadtrack_graph.benchmarks.endurance_clip import endurance_frame_id, ensure_endurance_clip, pingpong_index


def test_pingpong_index_plays_the_segment_back_and_forth():
    assert [pingpong_index(k, 4) for k in range(10)] == [0, 1, 2, 3, 2, 1, 0, 1, 2, 3]
    assert [pingpong_index(k, 2) for k in range(5)] == [0, 1, 0, 1, 0]
    assert pingpong_index(7, 1) == 0
    # Consecutive frames are neighbours in the segment (a continuous camera path).
    steps = np.abs(np.diff([pingpong_index(k, 37) for k in range(500)]))
    assert set(steps.tolist()) == {1}
    with pytest.raises(ValueError):
        pingpong_index(0, 0)


def test_endurance_clip_links_every_frame_to_its_segment_frame(tmp_path):
    segment = tmp_path / "segment"
    (segment / "img1").mkdir(parents=True)
    for i in range(3):
        (segment / "img1" / f"{i + 1:06d}.jpg").write_bytes(bytes([i]))
    folder, built = ensure_endurance_clip(segment, tmp_path / "clip", 7, 3)
    assert built
    names = sorted(p.name for p in folder.glob("*.jpg"))
    assert names == [f"{k + 1:06d}.jpg" for k in range(7)]
    assert [(folder / n).read_bytes()[0] for n in names] == [0, 1, 2, 1, 0, 1, 2]
    assert ensure_endurance_clip(segment, tmp_path / "clip", 7, 3) == (folder, False)
    _, rebuilt = ensure_endurance_clip(segment, tmp_path / "clip", 5, 3)
    assert rebuilt and len(list(folder.glob("*.jpg"))) == 5


def test_endurance_frame_ids_are_one_based_six_digit_positions():
    assert [endurance_frame_id(k) for k in (0, 41, 19999)] == ["000001", "000042", "020000"]
