"""Video files read with ``cv2.VideoCapture`` as a frame source (seeking, decoder failures), and the mp4v writer
every video the project writes is opened with (:func:`open_video_writer`)."""

from __future__ import annotations

import logging
import math
from pathlib import Path
from typing import Iterator

import cv2

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.frame_source import DEFAULT_FPS, Frame, FrameSource, frame_window

logger = logging.getLogger(__name__)

VIDEO_EXTENSIONS = (".mp4", ".avi", ".mov", ".mkv", ".mpg", ".mpeg", ".m4v", ".webm", ".ts", ".mts")

MAX_CONSECUTIVE_VIDEO_FAILURES = 25
"""A video whose decoder fails this many frames in a row is taken to have ended."""


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
        self.start, self.end = frame_window(start, end, count, path)
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


def open_video_writer(path: str | Path, fps: float, size: tuple[int, int]) -> cv2.VideoWriter:
    """An mp4v video writer at ``path`` (its folder made), ``fps`` frames per second, ``size`` (W, H) pixels.

    Raises:
        InputError: the writer cannot be opened (the folder is not writable, or no mp4v encoder).
    """
    path = Path(path)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
    except OSError as error:
        raise InputError(path, f"cannot make its folder ({error.strerror or error})") from error
    writer = cv2.VideoWriter(str(path), cv2.VideoWriter_fourcc(*"mp4v"), float(fps), tuple(int(v) for v in size))
    if not writer.isOpened():
        writer.release()
        raise InputError(path, "cannot open the video writer (mp4v)")
    return writer
