"""SoccerNet camera files: camera_NNNNN.json, one per frame."""

from __future__ import annotations

import re
from pathlib import Path

from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.io.jsonfile import read_json, write_json_atomic

CAMERA_FILE_PATTERN = re.compile(r"^camera_(\d+)\.json$")


def camera_file_name(frame_id: str | int) -> str:
    """``camera_00042.json`` for frame 42 (ids given as strings are kept as they are)."""
    return f"camera_{frame_id:05d}.json" if isinstance(frame_id, int) else f"camera_{frame_id}.json"


def read_camera_file(path: str | Path, width_px: int | None = None, height_px: int | None = None) -> Camera:
    """Read one SoccerNet camera file, rescaled to (width_px, height_px) when given.

    Raises:
        InputError: missing, empty, malformed, or a field missing / not finite.
    """
    data = read_json(path)
    if not isinstance(data, dict):
        raise InputError(path, f"expected a JSON object, got {type(data).__name__}")
    try:
        return Camera.from_soccernet_dict(data, width_px, height_px)
    except ValueError as exc:
        raise InputError(path, str(exc)) from None


def write_camera_file(path: str | Path, camera: Camera, width_px: int | None = None, height_px: int | None = None,
                      camera_id: str | None = None) -> None:
    """Write a SoccerNet camera file (atomically) with intrinsics at (width_px, height_px).

    camera_id: the broadcast camera the frame was taken with (``main``, ``high-behind-1``, ...), stored
    as an extra ``camera_id`` key (readers of the SoccerNet format look up their keys by name).
    """
    data = camera.to_soccernet_dict(width_px, height_px)
    if camera_id is not None:
        data["camera_id"] = str(camera_id)
    write_json_atomic(path, data, indent=None)


def list_camera_files(folder: str | Path) -> dict[str, Path]:
    """Frame id (the digits of camera_<id>.json) -> path, for a folder of camera files.

    Raises:
        InputError: the folder does not exist.
    """
    folder = Path(folder)
    if not folder.is_dir():
        raise InputError(folder, "camera folder not found")
    files = {}
    for path in sorted(folder.iterdir()):
        match = CAMERA_FILE_PATTERN.match(path.name)
        if match:
            files[match.group(1)] = path
    return files


def resolve_camera_folder(folder: str | Path) -> tuple[Path, dict[str, Path]]:
    """The folder of camera files meant by ``folder``: itself, or its ``cameras/`` (a run folder).

    A run folder (cameras/ inside, no camera file at its top) is the natural thing to pass
    where a cameras folder is expected; both are accepted and the folder used is returned
    so that the caller can say which.

    Returns:
        (the folder read, frame id -> path of its camera files).

    Raises:
        InputError: the folder does not exist, or holds no camera_<id>.json file (nor its cameras/).
    """
    folder = Path(folder)
    files = list_camera_files(folder)
    if not files and (folder / "cameras").is_dir():
        inner = folder / "cameras"
        files = list_camera_files(inner)
        if files:
            return inner, files
    if not files:
        raise InputError(folder, "no camera_<id>.json file in this folder (nor in its cameras/ subfolder); give a "
                                 "run folder or a folder of camera files")
    return folder, files
