"""An image folder whose first image has an odd size keeps its other frames (the clip size is the common one)."""

from __future__ import annotations

import logging

import cv2
import numpy as np

from broadtrack_graph.io.frames import open_frames


def test_odd_first_image_does_not_lose_the_other_frames(tmp_path, caplog):
    cv2.imwrite(str(tmp_path / "000001.png"), np.zeros((40, 50, 3), np.uint8))  # a title card of another size
    for i in range(2, 8):
        cv2.imwrite(str(tmp_path / f"{i:06d}.png"), np.full((48, 64, 3), i, np.uint8))
    with caplog.at_level(logging.WARNING):
        with open_frames(tmp_path) as source:
            assert (source.width_px, source.height_px) == (64, 48)
            frames = list(source)
    assert [f.image_bgr is not None for f in frames] == [False] + [True] * 6
    assert "image is 50x40, the clip is 64x48" in frames[0].problem
    assert "first image is 50x40 but most of the first 7 are 64x48" in caplog.text
