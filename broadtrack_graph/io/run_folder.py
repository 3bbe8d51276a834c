"""Track outputs: per-frame camera files, ``track.jsonl`` and ``summary.json``.

Layout of a run folder written by :class:`TrackWriter`::

    RUN/
      cameras/camera_<frame_id>.json          SoccerNet camera at the input resolution
      cameras_960x540/camera_<frame_id>.json  the same at 960x540 (on request)
      track.jsonl                             one JSON object per frame, flushed per frame
      summary.json                            run summary (rewritten periodically and at the end)

``track.jsonl`` fields per line (JSON ``null`` where unknown):

    frame (0-based index), frame_id, time_s, status, reason,
    pan_deg, tilt_deg, roll_deg, focal_px (at the input resolution), k1, position_m [x, y, z],
    pan_std_deg, tilt_std_deg, roll_std_deg, focal_std_px, k1_std, position_std_m [x, y, z],
    confidence (0..1), reinitialised (bool), active_factors (list of names), camera_file.

Every camera file is written atomically and every line is flushed before the
next frame starts, so a killed run leaves every frame written so far readable;
:func:`read_track` tolerates a truncated last line.

A run folder may also be a plain folder of ``camera_*.json`` files (another
tool's predictions, ground truth): :func:`read_track` reads those too.
"""

from __future__ import annotations

import collections
import json
import logging
import math
import time
from dataclasses import dataclass, field
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.errors import InputError
from broadtrack_graph.io.cameras import camera_file_name, list_camera_files, read_camera_file, write_camera_file
from broadtrack_graph.io.jsonfile import read_json, write_json_atomic

logger = logging.getLogger(__name__)

TRACK_FILE = "track.jsonl"
SUMMARY_FILE = "summary.json"
CAMERA_DIR = "cameras"
CAMERA_DIR_960 = "cameras_960x540"

STATUS_TRACKED = "tracked"
STATUS_REINITIALISED = "reinitialised"
STATUS_NO_PITCH = "no-pitch"
STATUS_NO_DETECTIONS = "no-detections"
STATUS_MISSING_FRAME = "missing-frame"
STATUS_FAILED = "failed"
STATUSES = (STATUS_TRACKED, STATUS_REINITIALISED, STATUS_NO_PITCH, STATUS_NO_DETECTIONS, STATUS_MISSING_FRAME, STATUS_FAILED)
"""Frame statuses. A record has a camera exactly when its status is tracked or reinitialised."""
STATUSES_WITH_CAMERA = (STATUS_TRACKED, STATUS_REINITIALISED)

STD_KEYS = ("pan_std_deg", "tilt_std_deg", "roll_std_deg", "focal_std_px", "k1_std", "position_std_m")
"""Keys of :attr:`TrackRecord.std` (position_std_m is a (3,) array, the others floats)."""


# --------------------------------------------------------------------------- the record


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


# --------------------------------------------------------------------------- writing


class TrackWriter:
    """Writes a run folder frame by frame (see the module docstring for the layout).

    Args:
        out_dir: run folder (created). Files of an earlier run in it (track.jsonl,
            summary.json, camera_*.json in its camera folders) are replaced.
        width_px, height_px: input resolution; records' cameras must be at it.
        also_960x540: also write cameras_960x540/ (the calibration benchmark's resolution).
        run_info: plain data stored in summary.json under "run" (input, mode, options).
        summary_every: rewrite summary.json every this many frames.

    Use as a context manager, or call :meth:`close` at the end; a run that is not
    closed leaves ``"complete": false`` in its last summary.
    """

    def __init__(
        self,
        out_dir: str | Path,
        width_px: int,
        height_px: int,
        also_960x540: bool = False,
        run_info: dict | None = None,
        summary_every: int = 100,
    ) -> None:
        if width_px <= 0 or height_px <= 0:
            raise ValueError(f"image size must be positive, got {width_px}x{height_px}")
        self.out_dir = Path(out_dir)
        self.width_px, self.height_px = int(width_px), int(height_px)
        self.also_960x540 = also_960x540
        self.run_info = dict(run_info or {})
        self.summary_every = max(1, int(summary_every))
        self.camera_dir = self.out_dir / CAMERA_DIR
        self.camera_dir_960 = self.out_dir / CAMERA_DIR_960
        try:
            self.camera_dir.mkdir(parents=True, exist_ok=True)
            if also_960x540:
                self.camera_dir_960.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(self.out_dir, f"cannot create output folder: {exc.strerror or exc}") from None
        removed = 0
        for folder in (self.camera_dir, self.camera_dir_960):
            if folder.is_dir():
                for stale in folder.glob("camera_*.json"):
                    stale.unlink()
                    removed += 1
        if removed:
            logger.info("%s: removed %d camera files of an earlier run", self.out_dir, removed)
        self._track = open(self.out_dir / TRACK_FILE, "w", encoding="utf-8")
        self._started_wall = time.time()
        self._started_utc = datetime.now(timezone.utc).isoformat(timespec="seconds")
        self._status_counts = {status: 0 for status in STATUSES}
        self._frames = 0
        self._reinitialisations = 0
        self._confidence_sum = 0.0
        self._confidence_count = 0
        self._last_frame_index: int | None = None
        self._recent_write_times: collections.deque = collections.deque(maxlen=26)
        self._last_record: TrackRecord | None = None
        self.closed = False
        self._write_summary(complete=False)

    # ----------------------------------------------------------------- per frame

    def write(self, record: TrackRecord) -> None:
        """Write one finished frame: its camera file(s), then its track line (flushed)."""
        if self.closed:
            raise RuntimeError("TrackWriter is closed")
        camera_file = None
        if record.camera is not None:
            camera = record.camera
            if (camera.width_px, camera.height_px) != (self.width_px, self.height_px):
                camera = camera.rescaled(self.width_px, self.height_px)
            name = camera_file_name(record.frame_id)
            write_camera_file(self.camera_dir / name, camera)
            if self.also_960x540:
                write_camera_file(self.camera_dir_960 / name, camera, 960, 540)
            camera_file = f"{CAMERA_DIR}/{name}"
            record = TrackRecord(**{**record.__dict__, "camera": camera})
        self._track.write(json.dumps(record.to_json(camera_file), allow_nan=False) + "\n")
        self._track.flush()
        self._frames += 1
        self._status_counts[record.status] += 1
        self._reinitialisations += int(record.reinitialised)
        if record.confidence is not None and math.isfinite(record.confidence):
            self._confidence_sum += record.confidence
            self._confidence_count += 1
        self._last_frame_index = record.frame_index
        self._last_record = record
        self._recent_write_times.append(time.perf_counter())
        if self._frames % self.summary_every == 0:
            self._write_summary(complete=False)

    def progress_postfix(self) -> dict[str, str]:
        """Fields for a tqdm bar (``bar.set_postfix(writer.progress_postfix(), refresh=False)``):
        current fps over the last 25 frames, the last frame's confidence and status."""
        times = self._recent_write_times
        fps = (len(times) - 1) / (times[-1] - times[0]) if len(times) > 1 and times[-1] > times[0] else None
        record = self._last_record
        return {
            "fps": "-" if fps is None else f"{fps:.1f}",
            "conf": "-" if record is None or record.confidence is None else f"{record.confidence:.2f}",
            "status": "-" if record is None else record.status,
        }

    # ----------------------------------------------------------------- summary

    def summary(self, complete: bool, extra: dict | None = None) -> dict:
        """The summary.json object for the frames written so far."""
        elapsed = time.time() - self._started_wall
        with_camera = sum(self._status_counts[s] for s in STATUSES_WITH_CAMERA)
        return {
            "complete": bool(complete),
            "started_utc": self._started_utc,
            "updated_utc": datetime.now(timezone.utc).isoformat(timespec="seconds"),
            "width_px": self.width_px,
            "height_px": self.height_px,
            "frames_written": self._frames,
            "frames_with_camera": with_camera,
            "completeness": with_camera / self._frames if self._frames else None,
            "status_counts": dict(self._status_counts),
            "reinitialisations": self._reinitialisations,
            "mean_confidence": self._confidence_sum / self._confidence_count if self._confidence_count else None,
            "last_frame_index": self._last_frame_index,
            "elapsed_s": round(elapsed, 3),
            "fps": round(self._frames / elapsed, 3) if elapsed > 0 else None,
            "files": {"track": TRACK_FILE, "cameras": CAMERA_DIR, "cameras_960x540": CAMERA_DIR_960 if self.also_960x540 else None},
            "run": self.run_info,
            **(extra or {}),
        }

    def _write_summary(self, complete: bool, extra: dict | None = None) -> dict:
        summary = self.summary(complete, extra)
        write_json_atomic(self.out_dir / SUMMARY_FILE, summary, indent=2)
        return summary

    def close(self, extra_summary: dict | None = None) -> dict:
        """Close track.jsonl and write the final summary (``"complete": true``); returns it."""
        if self.closed:
            return read_json(self.out_dir / SUMMARY_FILE)
        self._track.close()
        self.closed = True
        return self._write_summary(complete=True, extra=extra_summary)

    def __enter__(self) -> "TrackWriter":
        return self

    def __exit__(self, exc_type, exc, tb) -> None:
        if exc_type is None:
            self.close()
        else:
            # Keep what was written; the summary says the run did not finish.
            self._track.close()
            self.closed = True
            self._write_summary(complete=False, extra={"error": f"{exc_type.__name__}: {exc}"[:300]})


# --------------------------------------------------------------------------- reading


@dataclass
class Track:
    """A run read back from disk.

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


def read_track(run_dir: str | Path, width_px: int | None = None, height_px: int | None = None) -> Track:
    """Read a run folder written by :class:`TrackWriter`, or a folder of camera files.

    For a run folder the cameras are rebuilt from track.jsonl at the resolution of
    summary.json (or, when the run was killed before any summary, of its first
    camera file). A truncated or malformed LAST line is skipped with a warning
    (an interrupted run); a bad line elsewhere is an error. For a folder of
    ``camera_<id>.json`` files (no track.jsonl) every file becomes a tracked
    record, in id order, with frame_index the number of its id and no time.

    Args:
        run_dir: the folder (or its track.jsonl).
        width_px, height_px: rescale the cameras to this resolution (default: as written).

    Raises:
        InputError: folder missing, neither track.jsonl nor camera files, a bad line
            before the last one, or a bad camera file.
    """
    run_dir = Path(run_dir)
    if run_dir.is_file() and run_dir.name == TRACK_FILE:
        run_dir = run_dir.parent
    if not run_dir.is_dir():
        raise InputError(run_dir, "run folder not found")
    track_path = run_dir / TRACK_FILE
    if not track_path.is_file():
        return _read_camera_folder(run_dir, width_px, height_px)
    summary = {}
    if (run_dir / SUMMARY_FILE).is_file():
        try:
            summary = read_json(run_dir / SUMMARY_FILE)
        except InputError as exc:
            logger.warning("%s; resolution taken from the camera files", exc)
    file_w, file_h = summary.get("width_px"), summary.get("height_px")
    if not (isinstance(file_w, int) and isinstance(file_h, int)):
        file_w, file_h = _resolution_from_cameras(run_dir)
    with open(track_path, encoding="utf-8") as handle:
        lines = handle.read().split("\n")
    if lines and lines[-1] == "":
        lines.pop()
    records, skipped = [], 0
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        try:
            record = TrackRecord.from_json(json.loads(line), file_w, file_h)
        except (json.JSONDecodeError, ValueError) as exc:
            if number == len(lines):
                logger.warning("%s: line %d is truncated or malformed (interrupted run?); skipped", track_path, number)
                skipped += 1
                continue
            raise InputError(track_path, f"line {number}: {exc}") from None
        if width_px is not None and record.camera is not None:
            record.camera = record.camera.rescaled(width_px, height_px or round(file_h * width_px / file_w))
        records.append(record)
    out_w = width_px or file_w
    out_h = height_px or (file_h if width_px is None else round(file_h * width_px / file_w))
    return Track(records, out_w, out_h, summary, run_dir, skipped)


def _resolution_from_cameras(run_dir: Path) -> tuple[int, int]:
    folder = run_dir / CAMERA_DIR
    files = list_camera_files(folder) if folder.is_dir() else {}
    if not files:
        raise InputError(run_dir, f"no {SUMMARY_FILE} with width_px/height_px and no camera file to take the resolution from")
    camera = read_camera_file(next(iter(files.values())))
    return camera.width_px, camera.height_px


def _read_camera_folder(folder: Path, width_px: int | None, height_px: int | None) -> Track:
    if (folder / CAMERA_DIR).is_dir() and not list_camera_files(folder):
        folder = folder / CAMERA_DIR
    files = list_camera_files(folder)
    if not files:
        raise InputError(folder, f"neither {TRACK_FILE} nor camera_*.json files in folder")
    records = []
    for frame_id, path in sorted(files.items(), key=lambda item: int(item[0])):
        camera = read_camera_file(path, width_px, height_px)
        records.append(TrackRecord(int(frame_id), frame_id, None, camera))
    first = records[0].camera
    return Track(records, first.width_px, first.height_px, {}, folder, 0)
