"""Detections-file frames bounded by the clip or by a sane gap; what is dropped is reported."""

from __future__ import annotations

import logging

import numpy as np

from broadtrack_graph.io.detections import DetectionsFile
from broadtrack_graph.track.detection_frames import DEFAULT_MAX_GAP, bound_by_gap, bound_to_window
from broadtrack_graph.track.inputs import frames_from_detections
from broadtrack_graph.types.observations import FrameObservations

LINES = {"Middle line": np.array([[900.0, 100.0], [900.0, 400.0]])}


def detections(indices) -> DetectionsFile:
    file = DetectionsFile(image_size=(960, 540))
    for i in indices:
        file.frames[i] = FrameObservations(i, 960, 540, lines_px=dict(LINES))
        file.frame_ids[i] = f"{i + 1:06d}"
    return file


def test_a_stray_frame_number_is_dropped_and_reported(caplog):
    file = detections(list(range(20)) + [10_000_000])
    with caplog.at_level(logging.WARNING):
        frames = list(frames_from_detections(file))
    assert [f.frame_index for f in frames] == list(range(20))  # not 10 million frames
    assert "1 record(s) (frame 10000000) more than 750 frames away from the other 20 records dropped" in caplog.text


def test_the_largest_group_is_kept_even_when_the_stray_comes_first():
    file = detections([0] + list(range(5000, 5030)))
    assert bound_by_gap(file) == [0] and min(file.frames) == 5000 and len(file.frames) == 30


def test_gaps_up_to_the_limit_are_one_clip():
    file = detections([0, DEFAULT_MAX_GAP, 2 * DEFAULT_MAX_GAP])
    assert bound_by_gap(file) == [] and len(file.frames) == 3


def test_records_beyond_the_clip_are_dropped_with_a_warning(caplog):
    file = detections(range(0, 30))
    with caplog.at_level(logging.WARNING):
        assert bound_to_window(file, 0, 25) == [25, 26, 27, 28, 29]
    assert sorted(file.frames) == list(range(25)) and "5 record(s) (frame 25, 26, 27 ...) outside the frames 0..24" in caplog.text
