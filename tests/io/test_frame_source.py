"""Tests of io/frame_source.py: the start/end window and the source description."""

from __future__ import annotations

import numpy as np
import pytest

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.frame_source import Frame, FrameSource, frame_window


def test_frame_window_defaults_clamps_and_rejects():
    assert frame_window(None, None, 10, "clip") == (0, 10)
    assert frame_window(3, 99, 10, "clip") == (3, 10)
    assert frame_window(2, 5, 10, "clip") == (2, 5)
    with pytest.raises(InputError, match="must be >= 0"):
        frame_window(-1, None, 10, "clip")
    with pytest.raises(InputError, match="past the end"):
        frame_window(10, None, 10, "clip")
    with pytest.raises(InputError, match="greater than"):
        frame_window(4, 4, 10, "clip")


def test_frame_source_length_time_size_check_and_description():
    source = FrameSource()
    source.width_px, source.height_px, source.fps, source.start, source.end = 8, 6, 20.0, 3, 7
    assert len(source) == 4
    assert source._time(5) == pytest.approx(0.25)
    assert source._check_size(np.zeros((6, 8, 3), np.uint8)) is None
    assert source._check_size(np.zeros((6, 9, 3), np.uint8)) == "image is 9x6, the clip is 8x6"
    assert source.describe() == {"kind": "abstract", "path": None, "width_px": 8, "height_px": 6, "fps": 20.0,
                                 "start": 3, "end": 7, "frames": 4}
    assert Frame(0, "000001", 0.0, None, "x").is_missing
