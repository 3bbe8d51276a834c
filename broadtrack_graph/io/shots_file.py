"""The shots file (``shots.json``): the shots of a run's input, written by the tracker.

    {"shots": [{"start": 0, "end": 480, "kind": "main", "camera_id": "main", "boundary": "start",
                "views": {"main": 480}}, ...]}

start / end: first frame index and one past the last (0-based, end exclusive); kind: "main"
(the main camera), "other-camera" (another pitch camera), "pitch" (a pitch view no camera was
placed for), "close-up" or "crowd" (no pitch; no camera is written for their frames);
camera_id: the shot's camera ("main", "high-behind-1", ...), or null; boundary: how the shot
began ("start", "hard" cut, "dissolve", "view" change); views: frames per view kind.
"""

from __future__ import annotations

from pathlib import Path

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.jsonfile import read_json, write_json_atomic
from broadtrack_graph.io.run_folder import SHOTS_FILE  # noqa: F401  (the run folder names its files)
from broadtrack_graph.types.shot import Shot


def write_shots(path: str | Path, shots: list[Shot]) -> None:
    """Write ``shots.json`` (module docstring)."""
    data = {"shots": [{"start": int(s.start), "end": int(s.end), "kind": s.kind, "camera_id": s.camera_id,
                       "boundary": s.boundary, "views": {k: int(v) for k, v in s.views.items()}} for s in shots]}
    write_json_atomic(path, data, indent=1)


def read_shots(path: str | Path) -> list[Shot]:
    """Read a file written by :func:`write_shots`.

    Raises:
        InputError: missing, malformed, or a shot with end <= start.
    """
    data = read_json(path)
    try:
        shots = [Shot(int(s["start"]), int(s["end"]), str(s["kind"]),
                      None if s.get("camera_id") is None else str(s["camera_id"]), str(s.get("boundary", "hard")),
                      {str(k): int(v) for k, v in (s.get("views") or {}).items()}) for s in data["shots"]]
    except (KeyError, TypeError, ValueError):
        raise InputError(path, 'expected {"shots": [{"start": i, "end": j, "kind": k, "camera_id": c}, ...]}') from None
    for shot in shots:
        if shot.end <= shot.start:
            raise InputError(path, f"shot {shot.start}..{shot.end}: end must be after start")
    return shots
