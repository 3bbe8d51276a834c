"""The truth files of a synthetic broadcast clip (``synth --preset broadcast``), written and read here only.

In the clip folder, beside the game-state files::

    shots_truth.json       the true shots, in the tracker's shots.json format (io.shots_file):
                           {"shots": [{"start", "end", "kind", "camera_id", "boundary", "views"}]},
                           kind "main" / "other-camera" / "close-up" / "crowd", camera_id "main" /
                           "high-behind" / "low-16m" (null for close-up and crowd)
    tripods_truth.json     {camera_id: {"T_w": [x, y, z], "delta_m": d}} (metres, pitch frame)
    camera_ids_truth.json  {"camera_ids": [camera id or null, one per frame in frame order]}

Per-frame ground-truth cameras (``cameras/``) and annotations exist for pitch frames only.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.io.jsonfile import read_json, write_json_atomic
from broadtrack_graph.io.shots_file import read_shots, write_shots
from broadtrack_graph.io.tripod_file import tripods_from_json, tripods_to_json
from broadtrack_graph.types.shot import Shot

SHOTS_TRUTH_FILE = "shots_truth.json"
TRIPODS_TRUTH_FILE = "tripods_truth.json"
CAMERA_IDS_TRUTH_FILE = "camera_ids_truth.json"


@dataclass
class BroadcastTruth:
    """The truth of a broadcast clip.

    shots: the true shots (end exclusive, 0-based frame indices).
    tripods: camera id -> tripod.
    camera_ids: one per frame: the pitch camera id, or None on a frame with no pitch camera.
    """

    shots: list[Shot]
    tripods: dict[str, Tripod]
    camera_ids: list[str | None]


def has_broadcast_truth(folder: str | Path) -> bool:
    """True when the folder holds all three truth files."""
    folder = Path(folder)
    return all((folder / name).is_file() for name in (SHOTS_TRUTH_FILE, TRIPODS_TRUTH_FILE, CAMERA_IDS_TRUTH_FILE))


def write_broadcast_truth(folder: str | Path, shots: list[Shot], tripods: dict[str, Tripod],
                          camera_ids: list[str | None]) -> None:
    """Write the three truth files (module docstring) into ``folder``."""
    folder = Path(folder)
    write_shots(folder / SHOTS_TRUTH_FILE, shots)
    write_json_atomic(folder / TRIPODS_TRUTH_FILE, tripods_to_json(tripods), indent=1)
    write_json_atomic(folder / CAMERA_IDS_TRUTH_FILE, {"camera_ids": [None if c is None else str(c) for c in camera_ids]})


def read_broadcast_truth(folder: str | Path) -> BroadcastTruth:
    """Read the truth files of a broadcast clip folder.

    Raises:
        InputError: a file is missing or malformed, or the per-frame ids do not cover the shots.
    """
    folder = Path(folder)
    shots = read_shots(folder / SHOTS_TRUTH_FILE)
    tripods = tripods_from_json(read_json(folder / TRIPODS_TRUTH_FILE), folder / TRIPODS_TRUTH_FILE)
    path = folder / CAMERA_IDS_TRUTH_FILE
    data = read_json(path)
    ids = data.get("camera_ids") if isinstance(data, dict) else None
    if not isinstance(ids, list) or not all(c is None or isinstance(c, str) for c in ids):
        raise InputError(path, 'expected {"camera_ids": [camera id or null, ...]}')
    if shots and shots[-1].end != len(ids):
        raise InputError(path, f"{len(ids)} frame ids for shots ending at frame {shots[-1].end}")
    return BroadcastTruth(shots, tripods, list(ids))
