"""Folders of numbered images (``000001.jpg``, ``frame_2.png``, ...) as a frame source,
with the image decoding that detects truncated JPEG/PNG files.
"""

from __future__ import annotations

import logging
import math
import re
from pathlib import Path
from typing import Iterator

import cv2
import numpy as np

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.frame_size import clip_size
from broadtrack_graph.io.frame_source import DEFAULT_FPS, Frame, FrameSource, frame_window

logger = logging.getLogger(__name__)

IMAGE_EXTENSIONS = (".jpg", ".jpeg", ".png", ".bmp", ".tif", ".tiff", ".webp")

_DIGITS = re.compile(r"(\d+)")


def decode_image_file(path: Path) -> tuple[np.ndarray | None, str | None]:
    """Read one image file as BGR uint8, detecting truncated files.

    OpenCV decodes a truncated JPEG without failing (the missing part comes out
    grey), so JPEG files must end with the EOI marker and PNG files with the IEND
    chunk (trailing zero padding is allowed).

    Returns:
        (image (H, W, 3) uint8, None) or (None, one-line reason).
    """
    try:
        data = path.read_bytes()
    except OSError as exc:
        return None, f"cannot read file: {exc.strerror or exc}"
    if not data:
        return None, "empty file"
    tail = data.rstrip(b"\x00")
    if data[:2] == b"\xff\xd8" and not tail.endswith(b"\xff\xd9"):
        return None, "truncated JPEG (no end-of-image marker)"
    if data[:8] == b"\x89PNG\r\n\x1a\n" and b"IEND" not in tail[-16:]:
        return None, "truncated PNG (no IEND chunk)"
    image = cv2.imdecode(np.frombuffer(data, dtype=np.uint8), cv2.IMREAD_COLOR)
    if image is None:
        return None, "not a decodable image"
    return image, None


def _numeric_key(path: Path) -> tuple:
    """Sort key: the last run of digits in the stem, then the name (so frame_2 < frame_10)."""
    digits = _DIGITS.findall(path.stem)
    return (int(digits[-1]) if digits else math.inf, path.name)


def list_image_files(folder: Path) -> list[Path]:
    """Image files of a folder in numeric frame order (hidden files skipped)."""
    files = [
        p for p in folder.iterdir()
        if p.is_file() and p.suffix.lower() in IMAGE_EXTENSIONS and not p.name.startswith(".")
    ]
    return sorted(files, key=_numeric_key)


# --------------------------------------------------------------------------- image folders


class ImageFolderSource(FrameSource):
    """A folder of numbered images (``000001.jpg``, ``frame_2.png``, ...) in numeric order.

    The clip size is the most common size among the first readable images of the window
    (:func:`broadtrack_graph.io.frame_size.clip_size`); images of another size are yielded as missing.

    Args:
        folder: the folder.
        start, end: window of frame indices (0-based positions in the sorted list, end exclusive).
        fps: frame rate for time_s.

    Raises:
        InputError: folder missing, holds no image, or no image of the window can be decoded.
    """

    kind = "image-folder"

    def __init__(self, folder: str | Path, start: int | None = None, end: int | None = None, fps: float = DEFAULT_FPS) -> None:
        super().__init__()
        folder = Path(folder)
        if not folder.is_dir():
            raise InputError(folder, "image folder not found")
        self.path = folder
        self.files = list_image_files(folder)
        if not self.files:
            raise InputError(folder, f"no image files ({', '.join(IMAGE_EXTENSIONS)}) in folder")
        if not (fps > 0 and math.isfinite(fps)):
            raise InputError(folder, f"frame rate must be positive, got {fps}")
        self.fps = float(fps)
        self.start, self.end = frame_window(start, end, len(self.files), folder)
        self._first = self._first_readable()

    def _first_readable(self) -> tuple[int, np.ndarray]:
        found = clip_size(self.files, self.start, self.end, decode_image_file)  # the most common early size
        if found is not None:
            self.height_px, self.width_px = found[1].shape[:2]
            return found
        raise InputError(self.path, f"none of the {len(self)} images in frames {self.start}..{self.end - 1} can be decoded")

    def __iter__(self) -> Iterator[Frame]:
        first_index, first_image = self._first
        for index in range(self.start, self.end):
            path = self.files[index]
            if index == first_index:
                image, problem = first_image, None
            else:
                image, problem = decode_image_file(path)
            if image is not None:
                problem = self._check_size(image)
                if problem is not None:
                    image = None
            if problem is not None:
                logger.warning("%s: %s; frame %d marked missing", path, problem, index)
            yield Frame(index, path.stem, self._time(index), image, problem)
