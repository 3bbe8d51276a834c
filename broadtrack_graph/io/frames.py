"""Frame sources: one iterator over a video file, a folder of numbered images, or a
SoccerNet game-state sequence folder (``img1/`` + ``Labels-GameState.json``).

Every source yields :class:`Frame` items in clip order::

    with open_frames("clip.mp4", start=100, end=200) as source:
        print(source.width_px, source.height_px, source.fps, len(source))
        for frame in source:
            if frame.image_bgr is None:       # corrupt / unreadable: tracking goes on
                print(frame.frame_id, frame.problem)

Conventions:

* ``frame_index`` is the 0-based position in the whole input (not in the
  ``start``/``end`` window); ``start`` is inclusive and ``end`` exclusive.
* ``frame_id`` is the image file stem for image folders (``"000001"`` for
  ``000001.jpg``) and the 1-based, 6-digit position for videos (``"000001"`` for
  the first frame), which is SoccerNet's naming of game-state images.
* ``time_s = frame_index / fps``.
* A frame that cannot be decoded (truncated JPEG/PNG, garbage bytes, a size that
  differs from the clip's) is logged as one warning naming the file and yielded
  with ``image_bgr=None`` and ``problem`` set, so a tracker can mark it missing
  and go on.
* A video that cannot be opened, a missing path or a folder without images raises
  :class:`~broadtrack_graph.errors.InputError` naming the path.
"""

from __future__ import annotations

import logging
import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Iterator, Sequence

import cv2
import numpy as np

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.frame_size import clip_size
from broadtrack_graph.io.jsonfile import read_json

logger = logging.getLogger(__name__)

IMAGE_EXTENSIONS = (".jpg", ".jpeg", ".png", ".bmp", ".tif", ".tiff", ".webp")
VIDEO_EXTENSIONS = (".mp4", ".avi", ".mov", ".mkv", ".mpg", ".mpeg", ".m4v", ".webm", ".ts", ".mts")
GAMESTATE_FILE = "Labels-GameState.json"
GAMESTATE_IMAGE_DIR = "img1"
DEFAULT_FPS = 25.0
"""Frame rate assumed for image folders that do not state one (SoccerNet clips are 25 fps)."""

MAX_CONSECUTIVE_VIDEO_FAILURES = 25
"""A video whose decoder fails this many frames in a row is taken to have ended."""

_DIGITS = re.compile(r"(\d+)")


@dataclass(frozen=True)
class Frame:
    """One frame of a clip.

    frame_index: 0-based position in the whole input.
    frame_id: image file stem, or the 1-based 6-digit position for videos.
    time_s: frame_index / fps, seconds.
    image_bgr: (H, W, 3) uint8 BGR image, or None when the frame could not be read.
    problem: why image_bgr is None (one line), else None.
    """

    frame_index: int
    frame_id: str
    time_s: float
    image_bgr: np.ndarray | None
    problem: str | None = None

    @property
    def is_missing(self) -> bool:
        return self.image_bgr is None


class FrameSource:
    """Common interface of the frame sources (iterate, ``len``, context manager).

    Attributes:
        path: the input (file or folder); None for in-memory clips.
        width_px, height_px: size of every yielded image.
        fps: frames per second used for time_s.
        start, end: the window of frame indices yielded (end exclusive).
    """

    kind = "abstract"

    def __init__(self) -> None:
        self.path: Path | None = None
        self.width_px = 0
        self.height_px = 0
        self.fps = DEFAULT_FPS
        self.start = 0
        self.end = 0

    def __len__(self) -> int:
        """Number of frames the iteration yields (for videos: as the container states it)."""
        return max(0, self.end - self.start)

    def __iter__(self) -> Iterator[Frame]:
        raise NotImplementedError

    def close(self) -> None:
        """Release the underlying reader (no-op for folders)."""

    def __enter__(self) -> "FrameSource":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def describe(self) -> dict:
        """Plain-data description for run summaries."""
        return {
            "kind": self.kind, "path": None if self.path is None else str(self.path), "width_px": self.width_px,
            "height_px": self.height_px, "fps": self.fps, "start": self.start, "end": self.end, "frames": len(self),
        }

    def _time(self, frame_index: int) -> float:
        return frame_index / self.fps

    def _check_size(self, image: np.ndarray) -> str | None:
        if image.shape[0] != self.height_px or image.shape[1] != self.width_px:
            return f"image is {image.shape[1]}x{image.shape[0]}, the clip is {self.width_px}x{self.height_px}"
        return None


def _window(start: int | None, end: int | None, count: int, path) -> tuple[int, int]:
    """Validate --start/--end against the clip length; returns (start, end) with end exclusive."""
    start = 0 if start is None else int(start)
    end = count if end is None else min(int(end), count)
    if start < 0:
        raise InputError(path, f"--start must be >= 0, got {start}")
    if start >= count:
        raise InputError(path, f"--start {start} is past the end of the input ({count} frames)")
    if end <= start:
        raise InputError(path, f"--end {end} must be greater than --start {start}")
    return start, end


# --------------------------------------------------------------------------- image decoding


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
        self.start, self.end = _window(start, end, len(self.files), folder)
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


class GameStateSequenceSource(ImageFolderSource):
    """A SoccerNet game-state sequence folder: ``img1/`` images plus ``Labels-GameState.json``.

    The frame rate and image folder are read from the labels' ``info.frame_rate`` and
    ``info.im_dir`` when present (default 25 fps, ``img1``).

    Attributes:
        labels_path: the Labels-GameState.json (use it as ``--annotations``).
    """

    kind = "gamestate-sequence"

    def __init__(self, folder: str | Path, start: int | None = None, end: int | None = None, fps: float | None = None) -> None:
        folder = Path(folder)
        labels_path = folder / GAMESTATE_FILE
        info = {}
        if labels_path.is_file():
            labels = read_json(labels_path)
            info = labels.get("info") if isinstance(labels, dict) and isinstance(labels.get("info"), dict) else {}
        image_dir_name = info.get("im_dir") if isinstance(info.get("im_dir"), str) else GAMESTATE_IMAGE_DIR
        image_dir = folder / image_dir_name
        if not image_dir.is_dir():
            raise InputError(folder, f"game-state sequence without its {image_dir_name}/ image folder")
        if fps is None:
            rate = info.get("frame_rate")
            fps = float(rate) if isinstance(rate, (int, float)) and rate > 0 else DEFAULT_FPS
        super().__init__(image_dir, start, end, fps)
        self.sequence_path = folder
        self.labels_path = labels_path if labels_path.is_file() else None


# --------------------------------------------------------------------------- videos


class VideoSource(FrameSource):
    """A video file read with ``cv2.VideoCapture``.

    Frame ids are the 1-based, 6-digit positions (``"000001"`` is the first frame).
    ``len()`` is the frame count the container states; a stream that ends earlier
    stops with one warning. A frame the decoder fails on is yielded as missing;
    after ``MAX_CONSECUTIVE_VIDEO_FAILURES`` failures in a row the video is taken
    to have ended.

    Raises:
        InputError: file missing or cannot be opened / decoded at all.
    """

    kind = "video"

    def __init__(self, path: str | Path, start: int | None = None, end: int | None = None, fps: float | None = None) -> None:
        super().__init__()
        path = Path(path)
        if not path.is_file():
            raise InputError(path, "video file not found")
        self.path = path
        self._capture = cv2.VideoCapture(str(path))
        if not self._capture.isOpened():
            self._capture.release()
            raise InputError(path, "cannot open video (unknown format or corrupt file)")
        self.width_px = int(self._capture.get(cv2.CAP_PROP_FRAME_WIDTH))
        self.height_px = int(self._capture.get(cv2.CAP_PROP_FRAME_HEIGHT))
        count = int(self._capture.get(cv2.CAP_PROP_FRAME_COUNT))
        stated_fps = float(self._capture.get(cv2.CAP_PROP_FPS) or 0.0)
        self.fps = float(fps) if fps else (stated_fps if stated_fps > 0 and math.isfinite(stated_fps) else DEFAULT_FPS)
        if self.width_px <= 0 or self.height_px <= 0 or count <= 0:
            self._capture.release()
            raise InputError(path, f"video has no readable frames (size {self.width_px}x{self.height_px}, {count} frames)")
        self.start, self.end = _window(start, end, count, path)
        self._position = 0

    @staticmethod
    def frame_id_of(frame_index: int) -> str:
        """``"000001"`` for frame index 0."""
        return f"{frame_index + 1:06d}"

    def _seek(self, frame_index: int) -> None:
        if frame_index == self._position:
            return
        if frame_index > self._position and frame_index - self._position < 250:
            while self._position < frame_index and self._capture.grab():
                self._position += 1
        else:
            self._capture.set(cv2.CAP_PROP_POS_FRAMES, frame_index)
            self._position = int(round(self._capture.get(cv2.CAP_PROP_POS_FRAMES)))
        if self._position != frame_index:
            raise InputError(self.path, f"cannot seek to frame {frame_index} (reached {self._position})")

    def __iter__(self) -> Iterator[Frame]:
        self._seek(self.start)
        failures = 0
        for index in range(self.start, self.end):
            ok, image = self._capture.read()
            self._position += 1
            problem = None
            if not ok or image is None:
                failures += 1
                if failures >= MAX_CONSECUTIVE_VIDEO_FAILURES:
                    logger.warning(
                        "%s: video ended at frame %d of the %d it states", self.path, index - failures + 1, self.end
                    )
                    return
                problem = "video frame cannot be decoded"
                image = None
            else:
                failures = 0
                problem = self._check_size(image)
                if problem is not None:
                    image = None
            if problem is not None:
                logger.warning("%s: frame %d: %s; marked missing", self.path, index, problem)
            yield Frame(index, self.frame_id_of(index), self._time(index), image, problem)

    def close(self) -> None:
        self._capture.release()


# --------------------------------------------------------------------------- in memory


class ArrayFrameSource(FrameSource):
    """An in-memory clip (tests, synthetic clips): a sequence of BGR images or None.

    Args:
        images: sequence of (H, W, 3) uint8 images (None entries are yielded as missing).
        fps: frame rate for time_s.
        frame_ids: ids per image (default 1-based 6-digit, as for videos).
        start, end: window (end exclusive).
    """

    kind = "in-memory"

    def __init__(
        self,
        images: Sequence[np.ndarray | None],
        fps: float = DEFAULT_FPS,
        frame_ids: Sequence[str] | None = None,
        start: int | None = None,
        end: int | None = None,
    ) -> None:
        super().__init__()
        self.images = images
        self.frame_ids = list(frame_ids) if frame_ids is not None else [VideoSource.frame_id_of(i) for i in range(len(images))]
        if len(self.frame_ids) != len(images):
            raise ValueError(f"frame_ids has {len(self.frame_ids)} entries for {len(images)} images")
        first = next((im for im in images if im is not None), None)
        if first is None:
            raise ValueError("in-memory clip has no image")
        self.height_px, self.width_px = first.shape[:2]
        self.fps = float(fps)
        self.start, self.end = _window(start, end, len(images), "<in-memory clip>")

    def __iter__(self) -> Iterator[Frame]:
        for index in range(self.start, self.end):
            image = self.images[index]
            problem = "missing frame" if image is None else self._check_size(image)
            yield Frame(index, self.frame_ids[index], self._time(index), None if problem else image, problem)


# --------------------------------------------------------------------------- dispatch


def open_frames(path: str | Path, start: int | None = None, end: int | None = None, fps: float | None = None) -> FrameSource:
    """Open a video file, an image folder or a game-state sequence folder.

    Dispatch: a file -> :class:`VideoSource`; a folder holding ``img1/`` ->
    :class:`GameStateSequenceSource`; any other folder -> :class:`ImageFolderSource`.

    Args:
        path: the input.
        start, end: window of 0-based frame indices, end exclusive (None: whole input).
        fps: frame rate override (default: the video's, the labels', or 25).

    Raises:
        InputError: the path does not exist, or the source cannot be opened (see the classes).
    """
    path = Path(path)
    if path.is_file():
        if path.name == GAMESTATE_FILE:
            return GameStateSequenceSource(path.parent, start, end, fps)
        if path.suffix.lower() in IMAGE_EXTENSIONS:
            raise InputError(path, "a single image is not a clip: give the folder that holds the frames")
        return VideoSource(path, start, end, fps)
    if path.is_dir():
        if (path / GAMESTATE_IMAGE_DIR).is_dir():
            return GameStateSequenceSource(path, start, end, fps)
        return ImageFolderSource(path, start, end, fps or DEFAULT_FPS)
    raise InputError(path, "input not found (expected a video file, an image folder or a game-state sequence folder)")
