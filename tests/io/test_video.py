"""Tests of io/video.py: video files, seeking, undecodable and damaged videos."""

from __future__ import annotations

import logging

import cv2
import numpy as np
import pytest
from frame_files import H, W, frame_image, write_video

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.frames import open_frames
from broadtrack_graph.io.video import VideoSource


def test_video_source_ids_content_and_seek(tmp_path):
    path = tmp_path / "clip.mp4"
    write_video(path, 10, fps=20.0)
    with open_frames(path) as source:
        assert isinstance(source, VideoSource)
        assert (source.width_px, source.height_px, len(source)) == (W, H, 10)
        assert source.fps == pytest.approx(20.0)
        frames = list(source)
    assert [f.frame_id for f in frames] == [f"{k:06d}" for k in range(1, 11)]
    assert frames[3].time_s == pytest.approx(0.15)
    levels = [f.image_bgr.mean() for f in frames]
    assert np.allclose(levels, [20 * k + 10 for k in range(10)], atol=6)
    with VideoSource(path, start=6, end=9) as source:
        window = list(source)
    assert [f.frame_index for f in window] == [6, 7, 8]
    assert np.allclose([f.image_bgr.mean() for f in window], [130, 150, 170], atol=6)


def test_video_that_cannot_be_opened(tmp_path):
    bad = tmp_path / "bad.mp4"
    bad.write_bytes(b"\x00\x01garbage" * 100)
    with pytest.raises(InputError) as info:
        open_frames(bad)
    assert str(bad) in str(info.value) and "\n" not in str(info.value)
    with pytest.raises(InputError, match="not found"):
        open_frames(tmp_path / "missing.mp4")


def test_video_with_corrupt_frames_halfway_goes_on(tmp_path, caplog):
    path = tmp_path / "clip.mp4"
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), 25.0, (W, H))
    for k in range(12):
        image = frame_image(k)
        cv2.putText(image, str(k), (5, 40), cv2.FONT_HERSHEY_SIMPLEX, 1, (255, 255, 255), 2)
        writer.write(image)
    writer.release()
    data = bytearray(path.read_bytes())
    middle = len(data) // 2
    data[middle:middle + 400] = np.random.default_rng(0).integers(0, 256, 400, dtype=np.uint8).tobytes()
    path.write_bytes(bytes(data))
    with caplog.at_level(logging.WARNING, logger="broadtrack_graph.io.video"):
        frames = list(open_frames(path))
    missing = [f for f in frames if f.is_missing]
    assert 1 <= len(missing) <= 6
    assert all(f.problem for f in missing)
    assert frames[-1].frame_index >= 9 and not frames[-1].is_missing  # went on past the damage
    assert [f.frame_index for f in frames] == list(range(len(frames)))
    assert any(str(path) in r.getMessage() for r in caplog.records)



def test_video_frame_ids_are_one_based_six_digit_positions():
    assert [VideoSource.frame_id_of(i) for i in (0, 9, 123455)] == ["000001", "000010", "123456"]


def test_a_video_writer_is_opened_with_its_folder_or_the_path_is_named(tmp_path):
    from broadtrack_graph.io.video import open_video_writer

    out = tmp_path / "new" / "folder" / "clip.mp4"
    writer = open_video_writer(out, 25.0, (64, 48))
    for k in range(3):
        writer.write(np.full((48, 64, 3), 60 * k, np.uint8))
    writer.release()
    with VideoSource(out) as video:
        assert (video.width_px, video.height_px, len(video), video.fps) == (64, 48, 3, 25.0)
    (tmp_path / "a-file").write_text("x")
    with pytest.raises(InputError) as error:
        open_video_writer(tmp_path / "a-file" / "clip.mp4", 25.0, (64, 48))
    assert "a-file" in str(error.value)
