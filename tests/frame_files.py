"""Small clips on disk for the frame-source tests: flat grey frames (20 * k + 10) as images or a video."""

from __future__ import annotations

import cv2
import numpy as np

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
