"""Frame sources: image folders, videos, game-state sequences, corrupt frames, bad inputs."""

from __future__ import annotations

import json
import logging

import cv2
import numpy as np
import pytest

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.frames import (
    ArrayFrameSource,
    GameStateSequenceSource,
    ImageFolderSource,
    VideoSource,
    decode_image_file,
    open_frames,
)

W, H = 64, 48


def frame_image(k: int) -> np.ndarray:
    """A flat grey level per frame index (20 * k + 10), easy to recognise after lossy coding."""
    return np.full((H, W, 3), 20 * k + 10, dtype=np.uint8)


def write_folder(folder, count: int, ext: str = ".jpg", name=lambda k: f"{k + 1:06d}"):
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for k in range(count):
        path = folder / f"{name(k)}{ext}"
        assert cv2.imwrite(str(path), frame_image(k))
        paths.append(path)
    return paths


def write_video(path, count: int, fps: float = 25.0):
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), fps, (W, H))
    assert writer.isOpened()
    for k in range(count):
        writer.write(frame_image(k))
    writer.release()


# --------------------------------------------------------------------------- image folders


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


def test_bad_folders_raise_input_error_naming_the_path(tmp_path):
    with pytest.raises(InputError, match="not found") as info:
        open_frames(tmp_path / "nope")
    assert str(tmp_path / "nope") in str(info.value)
    empty = tmp_path / "empty"
    empty.mkdir()
    (empty / "notes.txt").write_text("x")
    with pytest.raises(InputError, match="no image files") as info:
        open_frames(empty)
    assert str(empty) in str(info.value)
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / "000001.jpg").write_bytes(b"junk")
    with pytest.raises(InputError, match="can be decoded"):
        open_frames(broken)
    write_folder(tmp_path / "ok", 3)
    with pytest.raises(InputError, match="past the end"):
        open_frames(tmp_path / "ok", start=3)
    with pytest.raises(InputError, match="greater than"):
        open_frames(tmp_path / "ok", start=2, end=2)
    with pytest.raises(InputError, match="single image"):
        open_frames(tmp_path / "ok" / "000001.jpg")


# --------------------------------------------------------------------------- game-state sequences


def test_gamestate_sequence_folder(tmp_path):
    sequence = tmp_path / "SNGS-001"
    write_folder(sequence / "img1", 4)
    labels = {"info": {"frame_rate": 10, "im_dir": "img1"}, "images": [], "annotations": []}
    (sequence / "Labels-GameState.json").write_text(json.dumps(labels))
    for path in (sequence, sequence / "Labels-GameState.json"):
        source = open_frames(path, start=1)
        assert isinstance(source, GameStateSequenceSource)
        assert source.fps == 10.0 and source.labels_path == sequence / "Labels-GameState.json"
        frames = list(source)
        assert [f.frame_id for f in frames] == ["000002", "000003", "000004"]
        assert frames[0].time_s == pytest.approx(0.1)
    with pytest.raises(InputError, match="img1"):
        GameStateSequenceSource(tmp_path)


# --------------------------------------------------------------------------- videos


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
    with caplog.at_level(logging.WARNING, logger="broadtrack_graph.io.frames"):
        frames = list(open_frames(path))
    missing = [f for f in frames if f.is_missing]
    assert 1 <= len(missing) <= 6
    assert all(f.problem for f in missing)
    assert frames[-1].frame_index >= 9 and not frames[-1].is_missing  # went on past the damage
    assert [f.frame_index for f in frames] == list(range(len(frames)))
    assert any(str(path) in r.getMessage() for r in caplog.records)


# --------------------------------------------------------------------------- in memory


def test_array_source():
    images = [frame_image(0), None, frame_image(2)]
    source = ArrayFrameSource(images, fps=5)
    frames = list(source)
    assert [f.frame_id for f in frames] == ["000001", "000002", "000003"]
    assert frames[1].is_missing and frames[1].problem == "missing frame"
    assert frames[2].time_s == pytest.approx(0.4)
    assert source.describe()["kind"] == "in-memory"
