"""The tripod file (``tripod.json``): {"T_w": [x, y, z], "delta_m": d, "fit": {...}}, and tripods by camera id.

A run that tracks several cameras may write one tripod per camera id; :func:`read_tripods_by_camera`
reads either form ({camera_id: {"T_w", "delta_m"}}, also under a "tripods" or "cameras" key).

Written by a run that fitted or used a tripod, read back with ``track --tripod`` for later
runs of the same camera (the synthetic clip's ground-truth tripod.json has the same form).
"""

from __future__ import annotations

import math
from pathlib import Path

from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.io.jsonfile import read_json, write_json_atomic

TRIPOD_FILE = "tripod.json"


def write_tripod(path: str | Path, tripod: Tripod, fit_info: dict | None = None) -> None:
    """Write ``tripod.json`` ({"T_w": [x, y, z], "delta_m": d}) for later runs of the same camera."""
    data = {"T_w": [float(v) for v in tripod.T_w], "delta_m": float(tripod.delta_m)}
    if fit_info:
        data["fit"] = {k: v for k, v in fit_info.items() if isinstance(v, (int, float, str, list, type(None)))}
    write_json_atomic(path, data, indent=1)


def read_tripod(path: str | Path) -> Tripod:
    """Read a tripod file written by :func:`write_tripod` (or the synthetic clip's tripod.json)."""
    data = read_json(path)
    try:
        T = [float(v) for v in data["T_w"]]
        delta = float(data["delta_m"])
    except (KeyError, TypeError, ValueError):
        raise InputError(path, "expected {\"T_w\": [x, y, z], \"delta_m\": d}") from None
    if len(T) != 3 or not all(map(math.isfinite, T + [delta])):
        raise InputError(path, "tripod values must be 3 finite coordinates and a finite delta_m")
    return Tripod((T[0], T[1], T[2]), delta)


def tripods_to_json(tripods: dict[str, Tripod]) -> dict:
    """{camera_id: {"T_w": [x, y, z], "delta_m": d}}."""
    return {str(cid): {"T_w": [float(v) for v in t.T_w], "delta_m": float(t.delta_m)} for cid, t in tripods.items()}


def tripods_from_json(data, source: str | Path) -> dict[str, Tripod]:
    """Inverse of :func:`tripods_to_json`; InputError naming ``source`` on a malformed entry."""
    if not isinstance(data, dict):
        raise InputError(source, 'expected {camera_id: {"T_w": [x, y, z], "delta_m": d}}')
    tripods = {}
    for cid, entry in data.items():
        try:
            T = [float(v) for v in entry["T_w"]]
            delta = float(entry["delta_m"])
        except (KeyError, TypeError, ValueError):
            raise InputError(source, f'camera {cid!r}: expected {{"T_w": [x, y, z], "delta_m": d}}') from None
        if len(T) != 3 or not all(map(math.isfinite, T + [delta])):
            raise InputError(source, f"camera {cid!r}: 3 finite coordinates and a finite delta_m expected")
        tripods[str(cid)] = Tripod((T[0], T[1], T[2]), delta)
    return tripods


def read_tripods_by_camera(path: str | Path, default_id: str = "main") -> dict[str, Tripod]:
    """Tripods by camera id from a tripod file of either form (module docstring).

    A single-tripod file gives ``{default_id: tripod}``.

    Raises:
        InputError: missing or malformed.
    """
    data = read_json(path)
    if isinstance(data, dict) and "T_w" in data:
        return {default_id: read_tripod(path)}
    if isinstance(data, dict):
        for key in ("tripods", "cameras"):
            if isinstance(data.get(key), dict):
                return tripods_from_json(data[key], path)
        entries = {k: v for k, v in data.items() if k != "fit"}
        return tripods_from_json(entries, path)
    raise InputError(path, 'expected {"T_w": [x, y, z], "delta_m": d} or {camera_id: {"T_w": ..., "delta_m": ...}}')
