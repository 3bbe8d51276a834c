"""The ``track.jsonl`` line of a :class:`~broadtrack_graph.types.track_record.TrackRecord` (the one owner of the format).

``track.jsonl`` fields per line (JSON ``null`` where unknown):

    frame (0-based index), frame_id, time_s, status, reason,
    pan_deg, tilt_deg, roll_deg, focal_px (at the input resolution), k1, position_m [x, y, z],
    pan_std_deg, tilt_std_deg, roll_std_deg, focal_std_px, k1_std, position_std_m [x, y, z],
    confidence (0..1), reinitialised (bool), active_factors (list of names), camera_file,
    camera_id (the broadcast camera of the frame: ``main``, ``high-behind-1``, ...; null when not known),
    repeat_of (the frame whose image this one repeats and whose estimate it carries; null for a frame of its own).
"""

from __future__ import annotations

import math

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.types.status import FrameStatus
from broadtrack_graph.types.track_record import STD_KEYS, TrackRecord


def record_to_json(record: TrackRecord, camera_file: str | None = None) -> dict:
    """The ``track.jsonl`` object of a record (``camera_file``: its camera file, relative to the run)."""
    cam = record.camera
    std = record.std
    position_std = std.get("position_std_m")
    return {
        "frame": int(record.frame_index),
        "frame_id": str(record.frame_id),
        "time_s": _num(record.time_s),
        "status": record.status.value,
        "reason": record.reason,
        "pan_deg": None if cam is None else cam.pan_deg,
        "tilt_deg": None if cam is None else cam.tilt_deg,
        "roll_deg": None if cam is None else cam.roll_deg,
        "focal_px": None if cam is None else float(cam.focal_px),
        "k1": None if cam is None else float(cam.k1),
        "position_m": None if cam is None else [float(v) for v in cam.position_m],
        "pan_std_deg": _num(std.get("pan_std_deg")),
        "tilt_std_deg": _num(std.get("tilt_std_deg")),
        "roll_std_deg": _num(std.get("roll_std_deg")),
        "focal_std_px": _num(std.get("focal_std_px")),
        "k1_std": _num(std.get("k1_std")),
        "position_std_m": None if position_std is None else [_num(v) for v in np.asarray(position_std).reshape(3)],
        "confidence": _num(record.confidence),
        "reinitialised": bool(record.reinitialised),
        "active_factors": list(record.active_factors),
        "camera_file": camera_file,
        "camera_id": record.camera_id,
        "repeat_of": record.repeat_of,
    }

def record_from_json(data: dict, width_px: int, height_px: int) -> TrackRecord:
    """Inverse of :func:`record_to_json` (the camera is rebuilt at width_px x height_px).

    Raises:
        ValueError: a field is missing or of the wrong type.
    """
    try:
        camera = None
        if data.get("focal_px") is not None:
            camera = Camera.from_degrees(
                float(data["focal_px"]), float(data["k1"]), float(data["pan_deg"]), float(data["tilt_deg"]),
                float(data["roll_deg"]), np.asarray(data["position_m"], dtype=float), width_px, height_px,
            )
        std = {}
        for key in STD_KEYS:
            value = data.get(key)
            if value is None:
                continue
            if key == "position_std_m":
                std[key] = np.array([np.nan if v is None else float(v) for v in value])
            else:
                std[key] = float(value)
        return TrackRecord(
            frame_index=int(data["frame"]),
            frame_id=str(data["frame_id"]),
            time_s=None if data.get("time_s") is None else float(data["time_s"]),
            camera=camera,
            std=std,
            confidence=None if data.get("confidence") is None else float(data["confidence"]),
            reinitialised=bool(data.get("reinitialised", False)),
            status=FrameStatus(str(data.get("status", FrameStatus.TRACKED if camera is not None else FrameStatus.FAILED))),
            reason=data.get("reason"),
            active_factors=tuple(data.get("active_factors") or ()),
            camera_id=None if data.get("camera_id") is None else str(data["camera_id"]),
            repeat_of=None if data.get("repeat_of") is None else int(data["repeat_of"]),
        )
    except (KeyError, TypeError, ValueError) as exc:
        raise ValueError(f"bad track record: {exc}") from None


def _num(value) -> float | None:
    if value is None:
        return None
    value = float(value)
    return value if math.isfinite(value) else None
