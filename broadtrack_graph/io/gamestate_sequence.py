"""SoccerNet game-state sequence folders (``img1/`` + ``Labels-GameState.json``) as a frame source."""

from __future__ import annotations

from pathlib import Path

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.annotations import GAMESTATE_FILE
from broadtrack_graph.io.frame_source import DEFAULT_FPS
from broadtrack_graph.io.image_folder import ImageFolderSource
from broadtrack_graph.io.jsonfile import read_json

GAMESTATE_IMAGE_DIR = "img1"


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
