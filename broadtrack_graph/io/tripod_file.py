"""The tripod file (``tripod.json``): {"T_w": [x, y, z], "delta_m": d, "fit": {...}}.

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
