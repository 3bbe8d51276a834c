"""Write detections files (see :mod:`broadtrack_graph.io.detections` for the format).

Two producers, so that detection and tracking can run on different machines and
ground truth can drive the tracker:

* :func:`export_detections`: run the project's detector over frames and write one
  record per frame. The weight-free detector names the markings with the tracker's
  predicted camera, so the online tracker runs alongside it
  (a :class:`~broadtrack_graph.track.frame_loop.TrackingRun` whose observer, a
  :class:`DetectionRecorder`, records what each frame hands the solver). Each frame's
  marking map is written as a PNG next to the file (the record's ``mask``), so the
  tracking side can compute the confidence and re-initialise from the map.
* :func:`import_annotations`: SoccerNet line annotations (a folder of per-image
  JSON files or a ``Labels-GameState.json``) become line detections.

Mask PNGs hold 255 on markings, :data:`MASK_FIELD_VALUE` on the playing field away
from markings and 0 elsewhere; the detections reader takes pixels above 127 as
markings, so they are valid binary masks for any reader.
"""

from __future__ import annotations

import logging
import re
import tempfile
import time
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np

from broadtrack_graph.actions.track import DetectorOptions, make_detector
from broadtrack_graph.detect.detector import Detections
from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.pitch import LINE_CLASSES, PitchTemplate
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.io.annotations import GAMESTATE_FILE, read_annotations
from broadtrack_graph.io.detections_writer import DetectionsWriter, normalized_lines_record
from broadtrack_graph.io.frames import open_frames
from broadtrack_graph.io.jsonfile import read_json
from broadtrack_graph.io.mask_png import write_mask_png
from broadtrack_graph.io.nbjw_keypoints import read_nbjw_predictions
from broadtrack_graph.io.run_folder import RunFolder
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.feed import run_loop
from broadtrack_graph.track.frame_loop import TrackingRun
from broadtrack_graph.track.inputs import FrameInput, frames_from_source
from broadtrack_graph.track.result import RunResult
from broadtrack_graph.track.run_context import RunContext
from broadtrack_graph.types.observations import FrameObservations

log = logging.getLogger(__name__)


@dataclass
class ExportSummary:
    """What a detections export or import wrote.

    path: the detections file.
    frames: frames seen; records: records written (one per frame with anything to say).
    frames_with_lines / frames_with_keypoints: records carrying named lines / keypoints.
    masks: mask PNGs written; mask_dir: their folder (None when none).
    seconds: wall time.
    track: the online run that named the markings (export only).
    skipped: one line per item left out (import: unknown classes, frames without a number).
    """

    path: Path
    frames: int = 0
    records: int = 0
    frames_with_lines: int = 0
    frames_with_keypoints: int = 0
    masks: int = 0
    mask_dir: Path | None = None
    seconds: float = 0.0
    track: RunResult | None = None
    skipped: list[str] = field(default_factory=list)

    def to_dict(self) -> dict:
        return {"path": str(self.path), "frames": self.frames, "records": self.records,
                "frames_with_lines": self.frames_with_lines, "frames_with_keypoints": self.frames_with_keypoints,
                "masks": self.masks, "mask_dir": None if self.mask_dir is None else str(self.mask_dir),
                "seconds": round(self.seconds, 3), "skipped": len(self.skipped),
                "track_dir": None if self.track is None else str(self.track.out_dir)}


# --------------------------------------------------------------------------- detector over frames


class DetectionRecorder:
    """Writes each frame's detections to a detections file: the observer of an online TrackingRun.

    Passed as the run's ``on_frame_done``. What is written for a frame is what the frame
    handed the solver (lines named with the predicted or re-initialised camera, keypoints
    of a learned detector, player boxes; flow is not part of the format). A frame that
    never reached the solver (no pitch, failed re-initialisation) gets the detector's raw
    output (usually only the marking map). A frame whose image is missing gets no record.

    Args:
        writer: the open DetectionsWriter.
        mask_dir: folder for the mask PNGs, or None for no masks.

    Attributes:
        stats: frames seen, records / masks written, records with lines / keypoints.
    """

    def __init__(self, writer: DetectionsWriter, mask_dir: Path | None) -> None:
        self.det_writer = writer
        self.mask_dir = mask_dir
        self.stats = {"frames": 0, "records": 0, "frames_with_lines": 0, "frames_with_keypoints": 0, "masks": 0}

    def __call__(self, frame: FrameInput, handed: FrameObservations | None, detections: Detections | None) -> None:
        """Record one processed frame (the :data:`~broadtrack_graph.track.run_context.FrameDone` observer)."""
        self.stats["frames"] += 1
        observations = handed
        if observations is None and detections is not None:
            observations = detections.to_observations(frame.frame_index)
        if observations is None:
            return
        mask_path = None
        if self.mask_dir is not None and detections is not None and detections.marking_mask is not None:
            target = self.mask_dir / f"{frame.frame_id}.png"
            if write_mask_png(target, detections.marking_mask, detections.field_mask):
                mask_path = target.relative_to(self.det_writer.path.parent).as_posix()
                self.stats["masks"] += 1
        self.det_writer.write(observations, frame_id=frame.frame_id, mask_path=mask_path)
        self.stats["records"] += 1
        self.stats["frames_with_lines"] += bool(observations.lines_px)
        self.stats["frames_with_keypoints"] += bool(observations.keypoints is not None and len(observations.keypoints))


def default_mask_dir(out_path: Path) -> Path:
    """Where export_detections puts the mask PNGs of OUT.jsonl: OUT_masks/ beside it."""
    return out_path.parent / f"{out_path.stem}_masks"


def export_detections(
    frames_path: str | Path,
    out_path: str | Path,
    config: TrackingConfig = TrackingConfig(),
    detector: DetectorOptions = DetectorOptions(),
    tripod: Tripod | None = None,
    reinit_position=None,
    start: int | None = None,
    end: int | None = None,
    write_masks: bool = True,
    track_dir: str | Path | None = None,
    progress: bool = True,
    pitch: PitchTemplate | None = None,
) -> ExportSummary:
    """Run the project's detector over frames and write a detections file (module docstring).

    Args:
        frames_path: video, folder of numbered frames or game-state sequence folder.
        out_path: the .jsonl file to write (masks go to :func:`default_mask_dir`).
        config: options of the online tracker that names the markings (mode is forced to online).
        detector: which detector (weight-free or ONNX).
        tripod / reinit_position: known tripod, or a re-initialisation guess of the camera position (metres), as for ``track``.
        start, end: frame range (0-based, end exclusive).
        write_masks: write the marking maps as PNGs.
        track_dir: keep the naming tracker's run folder here (default: a temporary folder, removed).
        progress: show a progress bar.

    Raises:
        InputError: unreadable input, bad model files, an output that cannot be written.
    """
    started = time.perf_counter()
    pitch = pitch or PitchTemplate()
    out_path = Path(out_path)
    if out_path.is_dir():
        raise InputError(out_path, "is a folder; give the detections file to write (e.g. detections.jsonl)")
    config = replace(config, mode="online")
    mask_dir = default_mask_dir(out_path) if write_masks else None
    positions = None if reinit_position is None else [tuple(float(v) for v in reinit_position)]
    run_info = {"input": str(frames_path), "detector": detector.kind, "purpose": "naming for a detections export",
                "detections_out": str(out_path)}
    made_detector = make_detector(detector, pitch)
    temporary = None
    if track_dir is None:
        temporary = tempfile.TemporaryDirectory(prefix="broadtrack-detect-")
        track_dir = temporary.name
    try:
        with open_frames(frames_path, start, end) as source:
            run_info["source"] = source.describe()
            try:
                writer = DetectionsWriter(out_path)
            except OSError as exc:
                raise InputError(out_path, f"cannot write: {exc.strerror or exc}") from None
            with writer:
                recorder = DetectionRecorder(writer, mask_dir)
                RunFolder(track_dir).clear()
                context = RunContext(config, made_detector, pitch, tripod, run_info=run_info,
                                     reinit_positions=positions, on_frame_done=recorder, progress=progress)
                run = TrackingRun(source.width_px, source.height_px, track_dir, context)
                run_loop(run, frames_from_source(source), len(source), "detect")
                result = run.finish({"detections_export": dict(recorder.stats)})
        stats = recorder.stats
        return ExportSummary(out_path, stats["frames"], stats["records"], stats["frames_with_lines"],
                             stats["frames_with_keypoints"], stats["masks"], mask_dir if stats["masks"] else None,
                             time.perf_counter() - started, None if temporary is not None else result)
    finally:
        if temporary is not None:
            temporary.cleanup()


# --------------------------------------------------------------------------- annotations


_NUMBER = re.compile(r"(\d+)$")


def _gamestate_order(path: Path) -> list[str]:
    """Image stems of a Labels-GameState.json in file-name order (the order of the img1/ frames)."""
    data = read_json(path)
    images = data.get("images") if isinstance(data, dict) else None
    if not isinstance(images, list):
        raise InputError(path, "not a game-state file: expected an 'images' list")
    stems = []
    for image in images:
        try:
            stems.append(Path(image["file_name"]).stem)
        except (KeyError, TypeError):
            raise InputError(path, f"image entry without file_name: {image!r}"[:200]) from None
    return sorted(set(stems), key=lambda s: (len(s), s))


def import_annotations(
    source: str | Path,
    out_path: str | Path,
    width_px: int | None = None,
    height_px: int | None = None,
    first_number: int | None = None,
) -> ExportSummary:
    """SoccerNet line annotations -> a detections file of line detections (normalised units).

    Frame indices: for a ``Labels-GameState.json`` (or a folder holding one), the position
    of the image in its ``images`` list sorted by file name (as ``track`` numbers the
    ``img1/`` frames); for a folder of ``NNNNN.json`` files, ``int(stem) - first_number``
    (default 1 unless a file numbered 0 exists, then 0), so frames without an annotation
    file stay in place. Frame ids are the file stems, so tracked cameras can be scored
    against the same annotations. "Line unknown" / "Goal unknown" are left out (they name
    no template element); files that cannot be read are reported and skipped.

    Args:
        source: folder of per-image JSON files, a Labels-GameState.json, or a folder with one.
        out_path: the .jsonl file to write.
        width_px, height_px: image size the annotations refer to (default: the game-state
            file's image size; required for a folder of per-image files).
        first_number: number of the stem of frame 0 (folders only).

    Raises:
        InputError: no annotations, no image size, a stem that is not a number.
    """
    started = time.perf_counter()
    source, out_path = Path(source), Path(out_path)
    annotations = read_annotations(source)
    summary = ExportSummary(out_path)
    summary.skipped += [f"{frame_id}: {message}" for frame_id, message in sorted(annotations.errors.items())]
    gamestate = source if source.is_file() else (source / GAMESTATE_FILE if (source / GAMESTATE_FILE).is_file() else None)
    if gamestate is not None:
        order = {stem: index for index, stem in enumerate(_gamestate_order(gamestate))}
        index_of = order.get
    else:
        numbers = {}
        for frame_id in annotations.frames:
            match = _NUMBER.search(frame_id)
            if match is None:
                summary.skipped.append(f"{source / (frame_id + '.json')}: file name has no frame number; skipped")
                continue
            numbers[frame_id] = int(match.group(1))
        if first_number is None:
            first_number = 0 if 0 in numbers.values() else 1
        index_of = lambda frame_id: None if frame_id not in numbers else numbers[frame_id] - first_number  # noqa: E731
    if (width_px is None) != (height_px is None):
        raise InputError(None, "give both --width and --height, or neither")
    records = []
    for frame_id, lines_norm in annotations.frames.items():
        index = index_of(frame_id)
        if index is None or index < 0:
            if index is not None:
                summary.skipped.append(f"{frame_id}: frame number below --first-number {first_number}; skipped")
            continue
        size = (width_px, height_px) if width_px is not None else annotations.image_sizes.get(frame_id)
        if size is None:
            raise InputError(source, "the annotations state no image size; give --width and --height")
        lines = {}
        for name, points in lines_norm.items():
            if name not in LINE_CLASSES:
                summary.skipped.append(f"{frame_id}: class '{name}' is not a template element; left out")
                continue
            lines[name] = np.round(np.asarray(points, float), 6).tolist()
        summary.frames += 1
        records.append((index, normalized_lines_record(index, frame_id, size, lines)))
    if not records:
        raise InputError(source, "no usable annotation to import")
    records.sort(key=lambda item: item[0])
    try:
        with DetectionsWriter(out_path) as writer:
            for _, record in records:
                writer.write_record(record)
    except OSError as exc:
        raise InputError(out_path, f"cannot write: {exc.strerror or exc}") from None
    summary.records = len(records)
    summary.frames_with_lines = sum(bool(r["lines"]) for _, r in records)
    summary.seconds = time.perf_counter() - started
    for line in summary.skipped:
        log.warning(line)
    return summary


def import_nbjw(source: str | Path, out_path: str | Path, width_px: int, height_px: int, clip: str | None = None,
                units: str = "normalized") -> ExportSummary:
    """NBJW / PnLCalib per-frame keypoint predictions (folder or zip) -> a detections file of keypoints.

    Each keypoint is written with its pitch position (``world``, metres, SoccerNet frame), its
    NBJW number (``id``) and its probability (``confidence``); frame index = the file's rank in
    numeric order, frame id = the file stem. Unknown keypoint numbers are reported (one line
    each) and skipped.

    Args:
        source: folder or zip archive of the per-frame JSON files.
        out_path: the .jsonl file to write.
        width_px, height_px: size of the images the predictions are for.
        clip: which clip, when the source holds several.
        units: "normalized" (NBJW's default) or "px".

    Raises:
        InputError: unreadable source, several clips without ``clip``, bad image size.
    """
    started = time.perf_counter()
    if width_px is None or height_px is None or width_px < 2 or height_px < 2:
        raise InputError(None, "--import nbjw needs the image size: give --width and --height")
    out_path = Path(out_path)
    predictions = read_nbjw_predictions(source, width_px, height_px, clip=clip, units=units)
    summary = ExportSummary(out_path, skipped=list(predictions.issues))
    try:
        with DetectionsWriter(out_path) as writer:
            for observations in predictions.frames:
                index = observations.frame_index
                writer.write(observations, predictions.frame_ids[index], keypoint_ids=predictions.keypoint_ids[index])
                summary.frames += 1
                summary.records += 1
                summary.frames_with_keypoints += observations.keypoints is not None
    except OSError as exc:
        raise InputError(out_path, f"cannot write: {exc.strerror or exc}") from None
    summary.seconds = time.perf_counter() - started
    for line in summary.skipped:
        log.warning(line)
    return summary
