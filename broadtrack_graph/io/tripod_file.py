"""The tripod file (``tripod.json``): {"T_w": [x, y, z], "delta_m": d, "fit": {...}, "cameras": {...}}.

``fit`` is the fit's report (its inliers, condition, why it was rejected or a provisional tripod stands in), one
per camera id ({camera_id: {...}}) for an offline run of several cameras.

A tripod whose place is uncertain (a provisional one, made from opening frames that disagree) carries ``sigma_m``
too, its uncertainty in metres (:class:`~broadtrack_graph.geometry.tripod.Tripod`); absent, 0.

Written by a run that fitted or used a tripod, read back with ``track --tripod`` for later
runs of the same cameras (the synthetic clip's ground-truth tripod.json has the same form).
The top level is the main camera's tripod (else the last camera's); ``cameras`` holds one
tripod per camera id of the run ({"main": {"T_w": ..., "delta_m": ...}, "high-corner-1": ...}).
A file of tripods by camera id alone ({camera_id: {"T_w", "delta_m"}}, also under a
``tripods`` key; the synthetic broadcast's truth) is read by :func:`read_tripods_by_camera`.
"""

from __future__ import annotations

import math
from pathlib import Path

from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.io.jsonfile import read_json, write_json_atomic

TRIPOD_FILE = "tripod.json"


def write_tripod(path: str | Path, tripod: Tripod, fit_info: dict | None = None,
                 cameras: dict[str, Tripod] | None = None) -> None:
    """Write ``tripod.json`` (module docstring) for later runs of the same cameras."""
    data = _tripod_dict(tripod)
    if fit_info:
        data["fit"] = _plain(fit_info)
    if cameras:
        data["cameras"] = tripods_to_json(dict(sorted(cameras.items())))
    write_json_atomic(path, data, indent=1)


def _plain(info: dict) -> dict:
    """The fit's report without its arrays (a run of several cameras reports one fit per camera id)."""
    return {k: _plain(v) if isinstance(v, dict) else v for k, v in info.items()
            if isinstance(v, (dict, int, float, str, list, type(None)))}


def read_tripod(path: str | Path) -> Tripod:
    """Read a tripod file written by :func:`write_tripod` (its top level) or the synthetic clip's tripod.json."""
    return _tripod_from(path, read_json(path))


def read_camera_tripods(path: str | Path) -> dict[str, Tripod]:
    """The per-camera tripods of a tripod file (its ``cameras``), or {} when it has none.

    Raises:
        InputError: missing or malformed file, or a malformed camera entry.
    """
    data = read_json(path)
    cameras = data.get("cameras") if isinstance(data, dict) else None
    return {} if cameras is None else tripods_from_json(cameras, path)


def read_tripods_by_camera(path: str | Path, default_id: str = "main") -> dict[str, Tripod]:
    """Tripods by camera id from a tripod file of any form (module docstring).

    A run's file gives its ``cameras`` (or its top level as ``default_id`` when it has none).

    Raises:
        InputError: missing or malformed.
    """
    data = read_json(path)
    if not isinstance(data, dict):
        raise InputError(path, 'expected {"T_w": [x, y, z], "delta_m": d} or {camera_id: {"T_w": ..., "delta_m": ...}}')
    for key in ("cameras", "tripods"):
        if isinstance(data.get(key), dict):
            return tripods_from_json(data[key], path)
    if "T_w" in data:
        return {default_id: _tripod_from(path, data)}
    return tripods_from_json({k: v for k, v in data.items() if k != "fit"}, path)


def tripods_to_json(tripods: dict[str, Tripod]) -> dict:
    """{camera_id: {"T_w": [x, y, z], "delta_m": d}}."""
    return {str(camera_id): _tripod_dict(tripod) for camera_id, tripod in tripods.items()}


def tripods_from_json(data, source: str | Path) -> dict[str, Tripod]:
    """Inverse of :func:`tripods_to_json`; an InputError naming ``source`` on a malformed entry."""
    if not isinstance(data, dict):
        raise InputError(source, 'expected {camera_id: {"T_w": [x, y, z], "delta_m": d}}')
    return {str(k): _tripod_from(source, v, f"cameras.{k}: ") for k, v in data.items()}


def _tripod_dict(tripod: Tripod) -> dict:
    data = {"T_w": [float(v) for v in tripod.T_w], "delta_m": float(tripod.delta_m)}
    if tripod.sigma_m > 0:  # a provisional tripod's own uncertainty: a later run holds the camera no tighter
        data["sigma_m"] = float(tripod.sigma_m)
    return data


def _tripod_from(path, data, where: str = "") -> Tripod:
    try:
        T = [float(v) for v in data["T_w"]]
        delta = float(data["delta_m"])
    except (KeyError, TypeError, ValueError):
        raise InputError(path, where + "expected {\"T_w\": [x, y, z], \"delta_m\": d}") from None
    if len(T) != 3 or not all(map(math.isfinite, T + [delta])):
        raise InputError(path, where + "tripod values must be 3 finite coordinates and a finite delta_m")
    try:
        sigma = float(data.get("sigma_m", 0.0))
    except (TypeError, ValueError):
        sigma = math.nan
    if not (math.isfinite(sigma) and sigma >= 0):
        raise InputError(path, where + "sigma_m must be a finite number of metres >= 0")
    return Tripod((T[0], T[1], T[2]), delta, sigma)
