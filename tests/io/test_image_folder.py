"""Tests of io/image_folder.py: numbered image folders, truncated and mismatched images."""

from __future__ import annotations

import logging

import cv2
import numpy as np
import pytest
from frame_files import H, W, write_folder

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.frames import open_frames
from broadtrack_graph.io.image_folder import ImageFolderSource, decode_image_file, list_image_files


def test_image_folder_yields_ids_times_and_images(tmp_path):
    write_folder(tmp_path, 5)
    source = open_frames(tmp_path)
    assert isinstance(source, ImageFolderSource)
    assert (source.width_px, source.height_px, source.fps, len(source)) == (W, H, 25.0, 5)
    frames = list(source)
    assert [f.frame_index for f in frames] == [0, 1, 2, 3, 4]
    assert [f.frame_id for f in frames] == ["000001", "000002", "000003", "000004", "000005"]
    assert [f.time_s for f in frames] == pytest.approx([0.0, 0.04, 0.08, 0.12, 0.16])
    for k, frame in enumerate(frames):
        assert frame.image_bgr.shape == (H, W, 3) and frame.image_bgr.dtype == np.uint8
        assert abs(frame.image_bgr.mean() - (20 * k + 10)) < 2.0
        assert frame.problem is None


def test_image_folder_numeric_order_and_window(tmp_path):
    write_folder(tmp_path, 12, ".png", name=lambda k: f"frame_{k}")
    source = ImageFolderSource(tmp_path, start=8, end=11, fps=10)
    frames = list(source)
    assert [f.frame_id for f in frames] == ["frame_8", "frame_9", "frame_10"]  # not frame_10 < frame_2
    assert [f.frame_index for f in frames] == [8, 9, 10]
    assert frames[0].time_s == pytest.approx(0.8)
    assert abs(frames[2].image_bgr.mean() - (20 * 10 + 10)) < 1.0
    assert len(source) == 3


def test_corrupt_jpeg_halfway_is_missing_and_tracking_goes_on(tmp_path, caplog):
    paths = write_folder(tmp_path, 6)
    data = paths[3].read_bytes()
    paths[3].write_bytes(data[: len(data) // 2])  # truncated: OpenCV alone would decode it grey
    paths[4].write_bytes(b"not an image at all" * 10)
    with caplog.at_level(logging.WARNING, logger="broadtrack_graph.io.frames"):
        frames = list(open_frames(tmp_path))
    assert len(frames) == 6
    assert [f.is_missing for f in frames] == [False, False, False, True, True, False]
    assert "truncated JPEG" in frames[3].problem
    assert "not a decodable image" in frames[4].problem
    assert abs(frames[5].image_bgr.mean() - 110) < 2.0
    messages = [r.getMessage() for r in caplog.records]
    assert any(str(paths[3]) in m for m in messages) and any(str(paths[4]) in m for m in messages)
    assert all("\n" not in m for m in messages)


def test_truncated_png_and_size_mismatch(tmp_path):
    paths = write_folder(tmp_path, 3, ".png")
    data = paths[1].read_bytes()
    paths[1].write_bytes(data[:-20])
    assert decode_image_file(paths[1])[0] is None
    cv2.imwrite(str(paths[2]), np.zeros((H + 2, W, 3), np.uint8))
    frames = list(open_frames(tmp_path))
    assert frames[1].is_missing and "truncated PNG" in frames[1].problem
    assert frames[2].is_missing and f"{W}x{H + 2}" in frames[2].problem


def test_first_images_corrupt_size_from_first_readable(tmp_path):
    paths = write_folder(tmp_path, 3)
    paths[0].write_bytes(b"\xff\xd8garbage")
    source = open_frames(tmp_path)
    assert (source.width_px, source.height_px) == (W, H)
    assert [f.is_missing for f in source] == [True, False, False]


def test_list_image_files_numeric_order_skips_hidden_and_other_files(tmp_path):
    for name in ("frame_10.png", "frame_2.jpg", "frame_1.JPG", ".frame_0.jpg", "notes.txt", "z.png"):
        (tmp_path / name).write_bytes(b"x")
    assert [p.name for p in list_image_files(tmp_path)] == ["frame_1.JPG", "frame_2.jpg", "frame_10.png", "z.png"]


def test_undecodable_folders_raise_input_error_naming_the_path(tmp_path):
    empty = tmp_path / "empty"
    empty.mkdir()
    (empty / "notes.txt").write_text("x")
    with pytest.raises(InputError, match="no image files") as info:
        ImageFolderSource(empty)
    assert str(empty) in str(info.value)
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / "000001.jpg").write_bytes(b"junk")
    with pytest.raises(InputError, match="can be decoded"):
        ImageFolderSource(broken)
