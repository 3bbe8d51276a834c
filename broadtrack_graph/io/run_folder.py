"""The run folder: one object that knows its layout and reads and writes each of its files.

Layout of a run folder (written frame by frame by :class:`~broadtrack_graph.io.track_writer.TrackWriter`)::

    RUN/
      cameras/camera_<frame_id>.json          SoccerNet camera at the input resolution
      cameras_960x540/camera_<frame_id>.json  the same at 960x540 (on request)
      track.jsonl                             one JSON object per frame, flushed per frame
                                              (fields: :mod:`broadtrack_graph.io.track_record`)
      summary.json                            run summary (rewritten periodically and at the end)
      tripod.json                             the tripod the run fitted or used (:mod:`broadtrack_graph.io.tripod_file`)
      pass1/                                  batch mode: the online first pass, itself a run folder
      shots.json                              shot boundaries (when the run writes them)

A new run into an existing folder first removes all of these (:meth:`RunFolder.clear`) and
nothing else. ``summary.json`` says ``"complete": true`` at the end of a run, and
``"interrupted": true`` (with counts matching the files) when Ctrl-C or SIGTERM stopped it.

``summary.json`` records what the run was made from under ``"run"`` (``input``, and
``detections``: the detections file it tracked from, or null).

Every camera file is written atomically and every line is flushed before the
next frame starts, so a killed run leaves every frame written so far readable;
:func:`read_track` tolerates a truncated last line.

A run folder may also be a plain folder of ``camera_*.json`` files (another
tool's predictions, ground truth): :func:`read_track` reads those too.
"""

from __future__ import annotations

import json
import logging
from pathlib import Path

from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.io.cameras import camera_file_name, list_camera_files, read_camera_file, write_camera_file
from broadtrack_graph.io.jsonfile import read_json, write_json_atomic
from broadtrack_graph.io.track_record import record_from_json
from broadtrack_graph.io.tripod_file import TRIPOD_FILE, read_tripod, write_tripod
from broadtrack_graph.types.track_record import RunRecords, TrackRecord

logger = logging.getLogger(__name__)

TRACK_FILE = "track.jsonl"
SUMMARY_FILE = "summary.json"
CAMERA_DIR = "cameras"
CAMERA_DIR_960 = "cameras_960x540"
PASS1_DIR = "pass1"
SHOTS_FILE = "shots.json"
RUN_ENTRIES = (CAMERA_DIR, CAMERA_DIR_960, PASS1_DIR, TRIPOD_FILE, SHOTS_FILE, SUMMARY_FILE, TRACK_FILE)
"""Everything a tracking run owns in its folder: a new run into the folder removes these and nothing else."""


class RunFolder:
    """A run folder (see the module docstring for its layout).

    Args:
        path: the folder (it need not exist yet).
    """

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)

    def __repr__(self) -> str:
        return f"RunFolder({str(self.path)!r})"

    # ----------------------------------------------------------------- layout

    @property
    def track_path(self) -> Path:
        return self.path / TRACK_FILE

    @property
    def summary_path(self) -> Path:
        return self.path / SUMMARY_FILE

    @property
    def tripod_path(self) -> Path:
        return self.path / TRIPOD_FILE

    @property
    def camera_dir(self) -> Path:
        """cameras/: camera files at the input resolution."""
        return self.path / CAMERA_DIR

    @property
    def camera_dir_960(self) -> Path:
        """cameras_960x540/: the same cameras at 960x540."""
        return self.path / CAMERA_DIR_960

    def camera_path(self, frame_id: str | int, at_960x540: bool = False) -> Path:
        """Path of one frame's camera file (``camera_<frame_id>.json``)."""
        return (self.camera_dir_960 if at_960x540 else self.camera_dir) / camera_file_name(frame_id)

    def pass1(self) -> "RunFolder":
        """The first (online) pass of a batch run, a run folder of its own."""
        return RunFolder(self.path / PASS1_DIR)

    def has_track(self) -> bool:
        return self.track_path.is_file()

    def has_summary(self) -> bool:
        return self.summary_path.is_file()

    def has_tripod(self) -> bool:
        return self.tripod_path.is_file()

    # ----------------------------------------------------------------- cameras

    def create(self, also_960x540: bool = False) -> None:
        """Create the folder and its camera folders.

        Raises:
            InputError: the folder cannot be created.
        """
        try:
            self.camera_dir.mkdir(parents=True, exist_ok=True)
            if also_960x540:
                self.camera_dir_960.mkdir(parents=True, exist_ok=True)
        except OSError as exc:
            raise InputError(self.path, f"cannot create output folder: {exc.strerror or exc}") from None

    def clear(self) -> list[str]:
        """Remove every entry a run owns (:data:`RUN_ENTRIES`) before a new run; returns the names removed.

        Other files in the folder (the user's) are left alone.

        Raises:
            InputError: an entry cannot be removed.
        """
        import shutil

        removed = []
        for name in RUN_ENTRIES:
            path = self.path / name
            try:
                if path.is_dir() and not path.is_symlink():
                    shutil.rmtree(path)
                elif path.exists() or path.is_symlink():
                    path.unlink()
                else:
                    continue
            except OSError as exc:
                raise InputError(path, f"cannot remove the earlier run's file: {exc.strerror or exc}") from None
            removed.append(name)
        if removed:
            logger.info("%s: removed the earlier run's %s", self.path, ", ".join(removed))
        return removed

    def remove_camera_files(self) -> int:
        """Delete the camera files of an earlier run (both camera folders); returns how many."""
        removed = 0
        for folder in (self.camera_dir, self.camera_dir_960):
            if folder.is_dir():
                for stale in folder.glob("camera_*.json"):
                    stale.unlink()
                    removed += 1
        return removed

    def write_camera(self, frame_id: str | int, camera: Camera, also_960x540: bool = False,
                     camera_id: str | None = None) -> str:
        """Write one frame's camera file(s) atomically (with the broadcast camera's id); returns its relative path."""
        name = camera_file_name(frame_id)
        write_camera_file(self.camera_dir / name, camera, camera_id=camera_id)
        if also_960x540:
            write_camera_file(self.camera_dir_960 / name, camera, 960, 540, camera_id=camera_id)
        return f"{CAMERA_DIR}/{name}"

    def camera_files(self) -> dict[str, Path]:
        """Frame id -> camera file in cameras/ ({} when the folder is absent)."""
        return list_camera_files(self.camera_dir) if self.camera_dir.is_dir() else {}

    # ----------------------------------------------------------------- summary

    def read_summary(self) -> dict:
        """summary.json.

        Raises:
            InputError: missing, empty or malformed.
        """
        return read_json(self.summary_path)

    def write_summary(self, summary: dict) -> None:
        """Write summary.json atomically (a reader never sees half a file)."""
        write_json_atomic(self.summary_path, summary, indent=2)

    def recorded_detections(self) -> Path | None:
        """The detections file the run tracked from (``summary["run"]["detections"]``), or None."""
        if not self.has_summary():
            return None
        path = (self.read_summary().get("run") or {}).get("detections")
        return None if path is None else Path(path)

    # ----------------------------------------------------------------- tripod

    def read_tripod(self) -> Tripod:
        """tripod.json (InputError when missing or malformed)."""
        return read_tripod(self.tripod_path)

    def write_tripod(self, tripod: Tripod, fit_info: dict | None = None, cameras: dict[str, Tripod] | None = None) -> None:
        write_tripod(self.tripod_path, tripod, fit_info, cameras)

    # ----------------------------------------------------------------- track

    def count_track_lines(self) -> int:
        """Non-empty lines of track.jsonl (0 when it does not exist)."""
        if not self.has_track():
            return 0
        return sum(1 for line in self.track_path.read_text(encoding="utf-8").splitlines() if line.strip())

    def read_track(self, width_px: int | None = None, height_px: int | None = None) -> RunRecords:
        """The run's records (see :func:`read_track`)."""
        if not self.path.is_dir():
            raise InputError(self.path, "run folder not found")
        if not self.has_track():
            return _read_camera_folder(self.path, width_px, height_px)
        summary = {}
        if self.has_summary():
            try:
                summary = self.read_summary()
            except InputError as exc:
                logger.warning("%s; resolution taken from the camera files", exc)
        file_w, file_h = summary.get("width_px"), summary.get("height_px")
        if not (isinstance(file_w, int) and isinstance(file_h, int)):
            file_w, file_h = self._resolution_from_cameras()
        track_path = self.track_path
        with open(track_path, encoding="utf-8") as handle:
            lines = handle.read().split("\n")
        if lines and lines[-1] == "":
            lines.pop()
        records, skipped = [], 0
        for number, line in enumerate(lines, start=1):
            if not line.strip():
                continue
            try:
                record = record_from_json(json.loads(line), file_w, file_h)
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
        return RunRecords(records, out_w, out_h, summary, self.path, skipped)

    def _resolution_from_cameras(self) -> tuple[int, int]:
        files = self.camera_files()
        if not files:
            raise InputError(self.path, f"no {SUMMARY_FILE} with width_px/height_px and no camera file to take the resolution from")
        camera = read_camera_file(next(iter(files.values())))
        return camera.width_px, camera.height_px


# --------------------------------------------------------------------------- reading


def read_track(run_dir: str | Path, width_px: int | None = None, height_px: int | None = None) -> RunRecords:
    """Read a run folder written by a track writer, or a folder of camera files.

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
    return RunFolder(run_dir).read_track(width_px, height_px)


def read_frame_camera_ids(run_dir: str | Path, default_id: str = "main") -> dict[int, str | None]:
    """frame index -> the ``camera_id`` field of each track.jsonl line (the camera a frame was tracked as).

    A line without the field (runs that tracked one camera) gives ``default_id`` when it has a
    camera (a focal length) and None otherwise. A truncated or malformed line is skipped.

    Raises:
        InputError: no track.jsonl in the folder.
    """
    folder = RunFolder(run_dir)
    if not folder.has_track():
        raise InputError(folder.track_path, "no track.jsonl")
    ids: dict[int, str | None] = {}
    for line in folder.track_path.read_text(encoding="utf-8").splitlines():
        try:
            data = json.loads(line) if line.strip() else None
        except json.JSONDecodeError:
            continue
        if not isinstance(data, dict) or not isinstance(data.get("frame"), int):
            continue
        if "camera_id" in data:
            ids[data["frame"]] = None if data["camera_id"] is None else str(data["camera_id"])
        else:
            ids[data["frame"]] = default_id if data.get("focal_px") is not None else None
    return ids


def _read_camera_folder(folder: Path, width_px: int | None, height_px: int | None) -> RunRecords:
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
    return RunRecords(records, first.width_px, first.height_px, {}, folder, 0)
