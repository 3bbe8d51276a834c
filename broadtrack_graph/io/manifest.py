"""The clip manifest of ``track-many``: one JSON object per line (JSON lines), one clip per line.

Format (blank lines and lines starting with ``#`` are ignored; relative paths are relative to
the manifest's folder)::

    {"input": "clips/a.mp4"}
    {"input": "clips/b_frames/", "name": "b", "tripod": "b_tripod.json", "start": 0, "end": 5000}
    {"detections": "det/c.jsonl", "mode": "batch", "chunk_frames": 1500}
    {"detections": "det/d.jsonl", "input": "clips/d.mp4"}

Keys of a clip:
    input: video file, folder of numbered frames or game-state sequence folder.
    detections: a detections file (JSON lines) to track from instead of a detector; with
        ``input`` too, the frames turn optical flow on.
    name: the clip's output folder under ``--out`` (default: the stem of input / detections);
        names must be unique.
    tripod: a ``tripod.json`` of an earlier run of this camera (held fixed).
    start, end: frame range, 0-based, end exclusive.
    mode: online | fixed-lag | batch (default: the command's ``--mode``).
    chunk_frames: batch mode: a clip longer than this is refined in chunks of this many frames
        in parallel (default: the command's ``--chunk-frames``).

Every problem is an :class:`~broadtrack_graph.errors.InputError` naming the manifest and the line.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from broadtrack_graph.errors import InputError
from broadtrack_graph.types.modes import MODES

KEYS = ("input", "detections", "name", "tripod", "start", "end", "mode", "chunk_frames")


@dataclass(frozen=True)
class ClipSpec:
    """One clip of a manifest (paths absolute or as given)."""

    name: str  # output folder name under --out
    input: Path | None = None  # video / frame folder / game-state folder
    detections: Path | None = None  # detections file (JSON lines)
    tripod: Path | None = None  # known tripod.json
    start: int | None = None  # first frame, 0-based
    end: int | None = None  # end frame, exclusive
    mode: str | None = None  # None: the command's --mode
    chunk_frames: int | None = None  # None: the command's --chunk-frames

    def as_dict(self) -> dict:
        """JSON-ready fields (paths as strings), for digests and reports."""
        return {k: (str(v) if isinstance(v, Path) else v) for k, v in self.__dict__.items()}


def clip_from_dict(entry: dict, base: Path, where: str) -> ClipSpec:
    """One manifest entry -> ClipSpec.

    Args:
        entry: the parsed JSON object.
        base: folder relative paths are resolved against.
        where: "<manifest>: line N" for error messages.
    """
    if not isinstance(entry, dict):
        raise InputError(None, f"{where}: expected a JSON object, got {type(entry).__name__}")
    unknown = sorted(set(entry) - set(KEYS))
    if unknown:
        raise InputError(None, f"{where}: unknown key(s) {', '.join(unknown)} (known: {', '.join(KEYS)})")
    paths = {}
    for key in ("input", "detections", "tripod"):
        value = entry.get(key)
        if value is None:
            continue
        if not isinstance(value, str) or not value:
            raise InputError(None, f"{where}: '{key}' must be a path string")
        path = Path(value).expanduser()
        path = path if path.is_absolute() else base / path
        if not path.exists():
            raise InputError(None, f"{where}: {key} {path} not found")
        paths[key] = path
    if "input" not in paths and "detections" not in paths:
        raise InputError(None, f"{where}: a clip needs 'input' or 'detections'")
    numbers = {}
    for key in ("start", "end", "chunk_frames"):
        value = entry.get(key)
        if value is None:
            continue
        if isinstance(value, bool) or not isinstance(value, int) or value < 0:
            raise InputError(None, f"{where}: '{key}' must be a non-negative integer, got {value!r}")
        numbers[key] = value
    if "start" in numbers and "end" in numbers and numbers["end"] <= numbers["start"]:
        raise InputError(None, f"{where}: end {numbers['end']} must be greater than start {numbers['start']}")
    if numbers.get("chunk_frames") is not None and numbers["chunk_frames"] < 20:
        raise InputError(None, f"{where}: chunk_frames must be at least 20, got {numbers['chunk_frames']}")
    mode = entry.get("mode")
    if mode is not None and mode not in MODES:
        raise InputError(None, f"{where}: mode must be one of {', '.join(MODES)}, got {mode!r}")
    name = entry.get("name")
    if name is None:
        name = clip_name(paths.get("input") or paths["detections"])
    if not isinstance(name, str) or not name or "/" in name or name.startswith((".", "_")):
        raise InputError(None, f"{where}: name must be a plain folder name (no '/', not starting with '.' or '_'), "
                               f"got {name!r}")
    return ClipSpec(name, paths.get("input"), paths.get("detections"), paths.get("tripod"), numbers.get("start"),
                    numbers.get("end"), mode, numbers.get("chunk_frames"))


def clip_name(path: Path) -> str:
    """Default clip name: the file's stem, or the folder's name."""
    path = Path(path)
    return (path.stem if path.is_file() else path.name) or "clip"


def read_manifest(path: str | Path) -> list[ClipSpec]:
    """Read a manifest (JSON lines, see the module docstring).

    Raises:
        InputError: missing or empty file, bad JSON, bad keys or values, duplicate names.
    """
    path = Path(path)
    if not path.is_file():
        raise InputError(path, "manifest not found")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(path, f"cannot read manifest: {exc}") from None
    clips = []
    for number, line in enumerate(text.splitlines(), start=1):
        line = line.strip()
        if not line or line.startswith("#"):
            continue
        where = f"{path}: line {number}"
        try:
            entry = json.loads(line)
        except json.JSONDecodeError as exc:
            raise InputError(None, f"{where}: not valid JSON ({exc.msg})") from None
        clips.append(clip_from_dict(entry, path.parent, where))
    if not clips:
        raise InputError(path, "manifest lists no clip")
    check_unique(clips, str(path))
    return clips


def clips_from_inputs(inputs: list[Path]) -> list[ClipSpec]:
    """Clips from command-line INPUTs: a ``.jsonl`` file is a detections file, anything else frames."""
    clips = []
    for path in inputs:
        key = "detections" if Path(path).suffix == ".jsonl" else "input"
        clips.append(clip_from_dict({key: str(path)}, Path.cwd(), f"input {path}"))
    check_unique(clips, "inputs")
    return clips


def check_unique(clips: list[ClipSpec], where: str) -> None:
    seen = set()
    for clip in clips:
        if clip.name in seen:
            raise InputError(None, f"{where}: clip name '{clip.name}' appears twice (give each clip a unique 'name')")
        seen.add(clip.name)


def write_manifest(path: str | Path, entries: list[dict]) -> Path:
    """Write a manifest: one JSON object per line (entries as in the module docstring)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("".join(json.dumps(entry) + "\n" for entry in entries), encoding="utf-8")
    return path
