"""One frame's estimate (:class:`TrackRecord`) and its ``track.jsonl`` line.

``track.jsonl`` fields per line (JSON ``null`` where unknown):

    frame (0-based index), frame_id, time_s, status, reason,
    pan_deg, tilt_deg, roll_deg, focal_px (at the input resolution), k1, position_m [x, y, z],
    pan_std_deg, tilt_std_deg, roll_std_deg, focal_std_px, k1_std, position_std_m [x, y, z],
    confidence (0..1), reinitialised (bool), active_factors (list of names), camera_file,
    camera_id (the broadcast camera of the frame: ``main``, ``high-behind-1``, ...; null when not known).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from broadtrack_graph.geometry.camera import Camera

STATUS_TRACKED = "tracked"
STATUS_REINITIALISED = "reinitialised"
STATUS_NO_PITCH = "no-pitch"
STATUS_NO_DETECTIONS = "no-detections"
STATUS_MISSING_FRAME = "missing-frame"
STATUS_FAILED = "failed"
STATUS_MOTION_PRIOR = "motion-prior"  # no detections: the solver carried the track on, but no camera is claimed
STATUS_OTHER_VIEW = "other-view"  # a close-up, crowd or other shot that is not the tracked camera's view
STATUS_UNPLACED = "unplaced"  # a pitch view no camera was found for (yet): the reason says when the next search runs
STATUSES = (
    # one line per status (a record's status is one of these)
    STATUS_TRACKED,
    STATUS_REINITIALISED,
    STATUS_NO_PITCH,
    STATUS_NO_DETECTIONS,
    STATUS_MISSING_FRAME,
    STATUS_FAILED,
    STATUS_MOTION_PRIOR,
    STATUS_OTHER_VIEW,
    STATUS_UNPLACED,
)
"""Frame statuses. A record has a camera exactly when its status is tracked or reinitialised: a
``motion-prior`` frame (carried by the motion prior alone, for at most ``max_motion_prior_frames``)
has none and never counts toward completeness; an ``other-view`` frame (a close-up, crowd or
another camera's shot) has none either."""
STATUSES_WITH_CAMERA = (STATUS_TRACKED, STATUS_REINITIALISED)

STD_KEYS = ("pan_std_deg", "tilt_std_deg", "roll_std_deg", "focal_std_px", "k1_std", "position_std_m")
"""Keys of :attr:`TrackRecord.std` (position_std_m is a (3,) array, the others floats)."""


@dataclass
class TrackRecord:
    """The estimate of one frame, as every tracker reports it (no gtsam types).

    frame_index: 0-based position in the input.
    frame_id: the frame's id (image stem, or 1-based 6-digit for videos).
    time_s: seconds from the start of the input.
    camera: the estimated camera at the input resolution, or None when the frame
        could not be estimated (then ``status`` and ``reason`` say why).
    std: standard deviations, keys in :data:`STD_KEYS` (missing keys = unknown).
    confidence: Jaccard confidence in [0, 1], or None when not computed.
    reinitialised: True when the camera came from a re-initialisation at this frame.
    status: one of :data:`STATUSES`.
    reason: one line explaining a status other than tracked, or None.
    active_factors: names of the factor kinds used for this frame (e.g. "lines", "flow", "tripod").
    camera_id: the broadcast camera the frame belongs to (None when not known).
    """

    frame_index: int
    frame_id: str
    time_s: float | None
    camera: Camera | None
    std: dict = field(default_factory=dict)
    confidence: float | None = None
    reinitialised: bool = False
    status: str = STATUS_TRACKED
    reason: str | None = None
    active_factors: tuple[str, ...] = ()
    camera_id: str | None = None

    def __post_init__(self) -> None:
        if self.status not in STATUSES:
            raise ValueError(f"unknown status '{self.status}', expected one of {STATUSES}")
        if (self.camera is not None) != (self.status in STATUSES_WITH_CAMERA):
            raise ValueError(f"status '{self.status}' with camera={'set' if self.camera is not None else 'None'}")
        unknown = set(self.std) - set(STD_KEYS)
        if unknown:
            raise ValueError(f"unknown std keys {sorted(unknown)}, expected some of {STD_KEYS}")
        self.active_factors = tuple(self.active_factors)

    @property
    def has_camera(self) -> bool:
        return self.camera is not None

    def to_json(self, camera_file: str | None = None) -> dict:
        """The ``track.jsonl`` object of this record."""
        cam = self.camera
        std = self.std
        position_std = std.get("position_std_m")
        return {
            "frame": int(self.frame_index),
            "frame_id": str(self.frame_id),
            "time_s": _num(self.time_s),
            "status": self.status,
            "reason": self.reason,
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
            "confidence": _num(self.confidence),
            "reinitialised": bool(self.reinitialised),
            "active_factors": list(self.active_factors),
            "camera_file": camera_file,
            "camera_id": self.camera_id,
        }

    @classmethod
    def from_json(cls, data: dict, width_px: int, height_px: int) -> "TrackRecord":
        """Inverse of :meth:`to_json` (the camera is rebuilt at width_px x height_px).

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
            return cls(
                frame_index=int(data["frame"]),
                frame_id=str(data["frame_id"]),
                time_s=None if data.get("time_s") is None else float(data["time_s"]),
                camera=camera,
                std=std,
                confidence=None if data.get("confidence") is None else float(data["confidence"]),
                reinitialised=bool(data.get("reinitialised", False)),
                status=str(data.get("status", STATUS_TRACKED if camera is not None else STATUS_FAILED)),
                reason=data.get("reason"),
                active_factors=tuple(data.get("active_factors") or ()),
                camera_id=None if data.get("camera_id") is None else str(data["camera_id"]),
            )
        except (KeyError, TypeError, ValueError) as exc:
            raise ValueError(f"bad track record: {exc}") from None


def _num(value) -> float | None:
    if value is None:
        return None
    value = float(value)
    return value if math.isfinite(value) else None




def std_from_covariance(covariance: np.ndarray) -> dict:
    """Standard deviations of a tracker state covariance, as :attr:`TrackRecord.std`.

    Args:
        covariance: (8, 8) covariance of ``[f, k1, pan, tilt, roll, Cx, Cy, Cz]``
            (px, -, rad, rad, rad, m, m, m), e.g. a marginal covariance from the solver.

    Returns:
        dict with the keys of :data:`STD_KEYS` (angles in degrees).

    Raises:
        ValueError: wrong shape.
    """
    covariance = np.asarray(covariance, dtype=float)
    if covariance.shape != (8, 8):
        raise ValueError(f"covariance: expected (8, 8), got {covariance.shape}")
    sigma = np.sqrt(np.clip(np.diag(covariance), 0.0, None))
    return {
        "focal_std_px": float(sigma[0]),
        "k1_std": float(sigma[1]),
        "pan_std_deg": math.degrees(sigma[2]),
        "tilt_std_deg": math.degrees(sigma[3]),
        "roll_std_deg": math.degrees(sigma[4]),
        "position_std_m": sigma[5:8].copy(),
    }


def covariance_from_std(std: dict) -> np.ndarray | None:
    """(8, 8) diagonal state covariance (px, -, rad, rad, rad, m, m, m) from :attr:`TrackRecord.std`, or None.

    Inverse of :func:`std_from_covariance` for the diagonal (``track.jsonl`` keeps no correlations).
    Unknown entries count as 0; None when no standard deviation is known.
    """
    if not std:
        return None
    position = std.get("position_std_m")
    sigma = np.array([
        std.get("focal_std_px") or 0.0, std.get("k1_std") or 0.0,
        math.radians(std.get("pan_std_deg") or 0.0), math.radians(std.get("tilt_std_deg") or 0.0),
        math.radians(std.get("roll_std_deg") or 0.0),
        *(np.zeros(3) if position is None else np.nan_to_num(np.asarray(position, dtype=float).reshape(3))),
    ])
    return np.diag(sigma ** 2)
