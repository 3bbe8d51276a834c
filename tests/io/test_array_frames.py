"""Tests of io/array_frames.py: in-memory clips."""

from __future__ import annotations

import pytest
from frame_files import frame_image

from broadtrack_graph.io.array_frames import ArrayFrameSource


def test_array_source():
    images = [frame_image(0), None, frame_image(2)]
    source = ArrayFrameSource(images, fps=5)
    frames = list(source)
    assert [f.frame_id for f in frames] == ["000001", "000002", "000003"]
    assert frames[1].is_missing and frames[1].problem == "missing frame"
    assert frames[2].time_s == pytest.approx(0.4)
    assert source.describe()["kind"] == "in-memory"


def test_array_source_window_and_bad_inputs():
    images = [frame_image(k) for k in range(4)]
    frames = list(ArrayFrameSource(images, frame_ids=["a", "b", "c", "d"], start=1, end=3))
    assert [(f.frame_index, f.frame_id) for f in frames] == [(1, "b"), (2, "c")]
    with pytest.raises(ValueError, match="3 entries for 4 images"):
        ArrayFrameSource(images, frame_ids=["a", "b", "c"])
    with pytest.raises(ValueError, match="no image"):
        ArrayFrameSource([None, None])
