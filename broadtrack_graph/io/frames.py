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

from pathlib import Path

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.annotations import GAMESTATE_FILE
from broadtrack_graph.io.frame_source import DEFAULT_FPS, FrameSource
from broadtrack_graph.io.gamestate_sequence import GAMESTATE_IMAGE_DIR, GameStateSequenceSource
from broadtrack_graph.io.image_folder import IMAGE_EXTENSIONS, ImageFolderSource
from broadtrack_graph.io.video import VideoSource


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
