"""Chunk planning and stitching (pure): kept ranges tile the clip, windows overlap, each frame once."""

from __future__ import annotations

from dataclasses import dataclass

import pytest

from broadtrack_graph.track.chunks import chunks_from_ranges, plan_chunks, stitch


@dataclass
class Item:
    frame_index: int
    source: int


def test_plan_tiles_the_clip_with_overlapping_windows():
    chunks = plan_chunks(100, 1050, 300, 20)
    assert [(c.keep_lo, c.keep_hi) for c in chunks] == [(100, 400), (400, 700), (700, 1050)]  # the 50-frame tail is merged
    assert [(c.lo, c.hi) for c in chunks] == [(100, 420), (380, 720), (680, 1050)]
    assert [c.index for c in chunks] == [0, 1, 2]
    assert plan_chunks(0, 1000, 300, 20)[-1].keep_hi == 1000
    assert len(plan_chunks(0, 50, 300, 20)) == 1


def test_plan_rejects_nonsense():
    with pytest.raises(ValueError):
        plan_chunks(10, 10, 300, 20)
    with pytest.raises(ValueError):
        chunks_from_ranges([(0, 10), (12, 20)], 0, 20, 5)  # a gap
    with pytest.raises(ValueError):
        chunks_from_ranges([(0, 10)], 0, 20, 5)  # does not reach the end


def test_shot_ranges_replace_the_regular_cut():
    chunks = chunks_from_ranges([(0, 37), (37, 120), (120, 130)], 0, 130, 10)
    assert [(c.lo, c.hi) for c in chunks] == [(0, 47), (27, 130), (110, 130)]


def test_stitch_takes_each_frame_from_its_own_chunk_once():
    chunks = plan_chunks(0, 100, 40, 5)
    pieces = [(c, [Item(i, c.index) for i in range(c.lo, c.hi)]) for c in reversed(chunks)]
    out = stitch(pieces)
    assert [item.frame_index for item in out] == list(range(100))
    assert all(chunks[item.source].keep_lo <= item.frame_index < chunks[item.source].keep_hi for item in out)
    assert [item.source for item in out if item.frame_index in (39, 40)] == [0, 1]


def test_stitch_rejects_duplicates_and_gaps():
    chunks = plan_chunks(0, 100, 40, 5)
    with pytest.raises(ValueError, match="twice"):
        stitch([(chunks[0], [Item(3, 0), Item(3, 0)])])
    with pytest.raises(ValueError, match="gap"):
        stitch([(chunks[0], []), (chunks[2], [])])
