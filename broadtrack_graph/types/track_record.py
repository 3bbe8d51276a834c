"""One frame's estimate (:class:`TrackRecord`) and a run's records read back (:class:`RunRecords`).

Their ``track.jsonl`` form is :mod:`broadtrack_graph.io.track_record`'s; the run folder that holds
them is :mod:`broadtrack_graph.io.run_folder`'s.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.types.status import FrameStatus

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
    status: a :class:`FrameStatus` (a plain status string is converted).
    reason: one line explaining a status other than tracked, or None.
    active_factors: names of the factor kinds used for this frame (e.g. "lines", "flow", "tripod").
    camera_id: the broadcast camera the frame belongs to (None when not known).
    repeat_of: the frame whose image this frame repeats (a duplicated frame of a frame-rate conversion), whose
        estimate it carries; None for a frame of its own.
    """

    frame_index: int
    frame_id: str
    time_s: float | None
    camera: Camera | None
    std: dict = field(default_factory=dict)
    confidence: float | None = None
    reinitialised: bool = False
    status: FrameStatus = FrameStatus.TRACKED
    reason: str | None = None
    active_factors: tuple[str, ...] = ()
    camera_id: str | None = None
    repeat_of: int | None = None

    def __post_init__(self) -> None:
        if self.status not in FrameStatus.__members__.values():
            raise ValueError(f"unknown status '{self.status}', expected one of {tuple(FrameStatus)}")
        self.status = FrameStatus(self.status)
        if (self.camera is not None) != self.status.has_camera:
            raise ValueError(f"status '{self.status}' with camera={'set' if self.camera is not None else 'None'}")
        unknown = set(self.std) - set(STD_KEYS)
        if unknown:
            raise ValueError(f"unknown std keys {sorted(unknown)}, expected some of {STD_KEYS}")
        self.active_factors = tuple(self.active_factors)

    @property
    def has_camera(self) -> bool:
        return self.camera is not None

    def repeated_at(self, frame_index: int, frame_id: str, time_s: float | None) -> "TrackRecord":
        """This frame's estimate for a later frame showing the same image (:attr:`repeat_of`): the same camera and
        status (a re-initialisation happened here, not there), the frame it repeats in the reason."""
        if self.repeat_of is not None:  # itself a repeat: the same source, the same reason
            source, reason = self.repeat_of, self.reason
        else:
            source = self.frame_index
            reason = f"the same image as frame {source}" + (f": {self.reason}" if self.reason else "")
        status = FrameStatus.TRACKED if self.status == FrameStatus.REINITIALISED else self.status
        return replace(self, frame_index=frame_index, frame_id=frame_id, time_s=time_s, reinitialised=False,
                       status=status, reason=reason, repeat_of=source)


def carry_repeats(records: list[TrackRecord]) -> list[TrackRecord]:
    """The records with every repeated frame's made its source's again (:meth:`TrackRecord.repeated_at`), for a pass
    that changed the sources (a smoother, the batch refinement, a recovery); records in frame order."""
    by_index: dict[int, TrackRecord] = {}
    out = []
    for record in records:
        source = by_index.get(record.repeat_of) if record.repeat_of is not None else None
        if source is not None:
            record = source.repeated_at(record.frame_index, record.frame_id, record.time_s)
        by_index[record.frame_index] = record
        out.append(record)
    return out


@dataclass
class RunRecords:
    """The records of one run, read back from its run folder (or a folder of camera files).

    records: per-frame records in file order.
    width_px, height_px: resolution of the cameras.
    summary: summary.json (empty when absent).
    path: the run folder.
    skipped_lines: lines of track.jsonl that could not be read (a truncated last line).
    """

    records: list[TrackRecord]
    width_px: int
    height_px: int
    summary: dict
    path: Path
    skipped_lines: int = 0

    def __len__(self) -> int:
        return len(self.records)

    @property
    def cameras(self) -> dict[str, Camera | None]:
        """frame id -> camera (None for frames without an estimate)."""
        return {r.frame_id: r.camera for r in self.records}

    @property
    def frame_indices(self) -> np.ndarray:
        """(N,) frame indices."""
        return np.array([r.frame_index for r in self.records], dtype=int)

    def by_frame_id(self) -> dict[str, TrackRecord]:
        return {r.frame_id: r for r in self.records}

    def states(self) -> np.ndarray:
        """(N, 8) ``[f_px, k1, pan_deg, tilt_deg, roll_deg, Cx_m, Cy_m, Cz_m]``; NaN rows for frames without camera.

        Note: angles in DEGREES here (the plots and comparisons use degrees).
        """
        out = np.full((len(self.records), 8), np.nan)
        for i, record in enumerate(self.records):
            cam = record.camera
            if cam is not None:
                out[i] = [cam.focal_px, cam.k1, cam.pan_deg, cam.tilt_deg, cam.roll_deg, *cam.position_m]
        return out

    def confidences(self) -> np.ndarray:
        """(N,) confidence per record, NaN where unknown."""
        return np.array([np.nan if r.confidence is None else r.confidence for r in self.records])


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
