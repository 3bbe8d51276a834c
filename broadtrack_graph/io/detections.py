"""The detections file: per-frame field detections as JSON lines, so any detector can drive the tracker.

One JSON object per line, one line per frame (frames without a line have no
detections). Every field but ``frame`` is optional::

    {"frame": 0, "frame_id": "000001", "image_size": [1920, 1080], "units": "px",
     "lines": {"Side line top": [[102.5, 311.0], [388.0, 290.5]], "Middle line": [[960.2, 300.1]]},
     "keypoints": [
        {"name": "Centre spot", "xy": [955.0, 610.0], "confidence": 0.92},
        {"world": [11.0, -20.16, 0.0], "xy": [1210.0, 402.0], "confidence": 0.71}],
     "mask": "masks/000001.png",
     "players": [[812, 500, 840, 580]]}

* ``frame``: 0-based frame index in the clip (required).
* ``image_size``: [W, H] in pixels that the coordinates refer to (else the file's
  first stated size, else the size passed to the reader).
* ``units``: ``"px"`` (default) or ``"normalized"`` (0..1 of the image, SoccerNet's
  ``x * (W - 1)`` rule).
* ``lines``: SoccerNet class name -> points ``[x, y]`` (or ``{"x":..,"y":..}``) on that marking.
* ``keypoints``: each with ``xy``, a ``confidence`` in [0, 1] (default 1), and either
  ``name`` (a keypoint of the project's template, see ``PitchTemplate.keypoints``)
  or ``world`` [x, y, z] in metres (SoccerNet frame, z down), so detectors with their
  own keypoint sets need no code change.
* ``mask``: path (relative to the file) of a binary marking mask image; ``players``:
  boxes [x0, y0, x1, y1] in the same units as the points.

Reading is forgiving where it can be: a keypoint with low confidence, a duplicate,
NaN coordinates, a point outside the image or an unknown name is skipped and
reported; a malformed or truncated line skips that frame and is reported; only a
missing or empty file is an error.
"""

from __future__ import annotations

import json
import logging
import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.pitch import LINE_CLASSES, PitchTemplate
from broadtrack_graph.io.jsonfile import read_text
from broadtrack_graph.types.observations import FrameObservations, KeypointObservations

log = logging.getLogger(__name__)

DEFAULT_MIN_CONFIDENCE = 0.3


@dataclass
class DetectionsFile:
    """What a detections file holds.

    frames: frame index -> observations (pixels at image_size).
    frame_ids: frame index -> frame id string (file stem), when given.
    mask_paths: frame index -> resolved mask path, when given.
    image_size: (W, H) of the coordinates.
    issues: one line per skipped item or frame, naming the file and line.
    """

    frames: dict[int, FrameObservations] = field(default_factory=dict)
    frame_ids: dict[int, str] = field(default_factory=dict)
    mask_paths: dict[int, Path] = field(default_factory=dict)
    image_size: tuple[int, int] | None = None
    issues: list[str] = field(default_factory=list)

    @property
    def last_frame(self) -> int:
        return max(self.frames, default=-1)


def _xy(value) -> tuple[float, float]:
    if isinstance(value, dict):
        return float(value["x"]), float(value["y"])
    if isinstance(value, (list, tuple)) and len(value) == 2:
        return float(value[0]), float(value[1])
    raise ValueError(f"expected [x, y] or {{'x', 'y'}}, got {value!r}")


def _inside(xy: np.ndarray, width: int, height: int) -> np.ndarray:
    return (xy[:, 0] >= -0.5) & (xy[:, 0] <= width - 0.5) & (xy[:, 1] >= -0.5) & (xy[:, 1] <= height - 0.5)


def parse_detection_record(
    record: dict,
    where: str,
    pitch: PitchTemplate,
    default_size: tuple[int, int] | None,
    min_confidence: float = DEFAULT_MIN_CONFIDENCE,
) -> tuple[FrameObservations, list[str]]:
    """Turn one JSON object into FrameObservations; returns it with the issues met.

    Raises:
        ValueError: the record has no usable frame index or image size.
    """
    issues: list[str] = []
    frame = record.get("frame")
    if not isinstance(frame, int) or isinstance(frame, bool) or frame < 0:
        raise ValueError(f"'frame' must be a non-negative integer, got {frame!r}")
    size = record.get("image_size", default_size)
    if size is None:
        raise ValueError("no 'image_size' (and none given to the reader)")
    width, height = int(size[0]), int(size[1])
    if len(size) != 2 or width < 2 or height < 2 or width > 100_000 or height > 100_000:
        raise ValueError(f"bad image_size {size!r}")
    units = record.get("units", "px")
    if units not in ("px", "normalized"):
        raise ValueError(f"'units' must be 'px' or 'normalized', got {units!r}")
    scale = np.array([width - 1.0, height - 1.0]) if units == "normalized" else np.ones(2)

    lines_px: dict[str, np.ndarray] = {}
    raw_lines = record.get("lines") or {}
    if not isinstance(raw_lines, dict):
        raise ValueError(f"'lines' must be an object of class name -> points, got {type(raw_lines).__name__}")
    for raw_name, points in raw_lines.items():
        name = str(raw_name).strip()
        if name not in LINE_CLASSES:
            issues.append(f"{where}: unknown line class '{raw_name}' skipped")
            continue
        try:
            xy = np.array([_xy(p) for p in points], dtype=float).reshape(-1, 2) * scale
        except (ValueError, KeyError, TypeError) as exc:
            issues.append(f"{where}: class '{name}': {exc}; class skipped")
            continue
        finite = np.isfinite(xy).all(axis=1)
        inside = finite & _inside(np.where(finite[:, None], xy, 0.0), width, height)
        if (~finite).any():
            issues.append(f"{where}: class '{name}': {int((~finite).sum())} non-finite point(s) skipped")
        if (finite & ~inside).any():
            issues.append(f"{where}: class '{name}': {int((finite & ~inside).sum())} point(s) outside the image skipped")
        xy = np.unique(xy[inside], axis=0) if inside.any() else np.zeros((0, 2))
        if len(xy):
            lines_px[name] = xy

    uv_list, world_list, confidence_list, names = [], [], [], []
    seen: set[tuple] = set()
    raw_keypoints = record.get("keypoints") or []
    if not isinstance(raw_keypoints, list):
        raise ValueError(f"'keypoints' must be a list, got {type(raw_keypoints).__name__}")
    for index, keypoint in enumerate(raw_keypoints):
        label = f"{where}: keypoint {index}"
        if not isinstance(keypoint, dict):
            issues.append(f"{label}: expected an object with 'xy'; skipped")
            continue
        try:
            uv = np.array(_xy(keypoint["xy"])) * scale
            confidence = float(keypoint.get("confidence", 1.0))
        except (ValueError, KeyError, TypeError) as exc:
            issues.append(f"{label}: {exc}; skipped")
            continue
        if not (np.isfinite(uv).all() and math.isfinite(confidence)):
            issues.append(f"{label}: non-finite value; skipped")
            continue
        if confidence < min_confidence:
            issues.append(f"{label}: confidence {confidence:.2f} below {min_confidence:.2f}; skipped")
            continue
        if not _inside(uv[None], width, height)[0]:
            issues.append(f"{label}: outside the {width}x{height} image; skipped")
            continue
        name = str(keypoint.get("name", "")).strip()
        if "world" in keypoint:
            try:
                world = np.array([float(v) for v in keypoint["world"]], dtype=float)
            except (TypeError, ValueError):
                world = np.full(3, np.nan)
            if world.shape != (3,) or not np.isfinite(world).all():
                issues.append(f"{label}: 'world' must be 3 finite numbers; skipped")
                continue
        elif name in pitch.keypoints:
            world = pitch.keypoints[name]
        else:
            issues.append(f"{label}: unknown keypoint name '{name}' and no 'world'; skipped")
            continue
        key = tuple(np.round(world, 3))
        if key in seen:
            issues.append(f"{label}: duplicate of an earlier keypoint at {[float(v) for v in key]}; skipped")
            continue
        seen.add(key)
        uv_list.append(uv)
        world_list.append(world)
        confidence_list.append(confidence)
        names.append(name)
    keypoints = None
    if uv_list:
        keypoints = KeypointObservations(np.array(uv_list), np.array(world_list), np.array(confidence_list), names)

    players = None
    if record.get("players"):
        try:
            boxes = np.array(record["players"], dtype=float).reshape(-1, 4) * np.tile(scale, 2)
            players = boxes[np.isfinite(boxes).all(axis=1)]
        except (ValueError, TypeError):
            issues.append(f"{where}: 'players' must be a list of [x0, y0, x1, y1]; ignored")
    observations = FrameObservations(frame, width, height, lines_px=lines_px, keypoints=keypoints, player_boxes_px=players)
    return observations, issues


def read_detections(
    path: str | Path,
    pitch: PitchTemplate | None = None,
    image_size: tuple[int, int] | None = None,
    min_confidence: float = DEFAULT_MIN_CONFIDENCE,
    frame_range: tuple[int | None, int | None] | None = None,
) -> DetectionsFile:
    """Read a detections file (JSON lines), skipping and reporting what cannot be used.

    Args:
        path: the .jsonl file.
        pitch: template for keypoint names (default 105 x 68).
        image_size: (W, H) for records that do not state it.
        min_confidence: keypoints below this confidence are skipped.
        frame_range: (start, end) frame indices (end exclusive, None: open): records of other
            frames are skipped before they are parsed (a window of a long match reads only its frames).

    Raises:
        InputError: the file is missing or holds no usable record.
    """
    path = Path(path)
    pitch = pitch or PitchTemplate()
    text = read_text(path, "detections file")
    result = DetectionsFile(image_size=image_size)
    lines = text.splitlines()
    low, high = frame_range if frame_range is not None else (None, None)
    for number, line in enumerate(lines, start=1):
        if not line.strip():
            continue
        if frame_range is not None and line.startswith('{"frame": '):
            frame = _frame_of_line(line)
            if frame is not None and ((low is not None and frame < low) or (high is not None and frame >= high)):
                continue
        where = f"{path}:{number}"
        try:
            record = json.loads(line)
        except json.JSONDecodeError as exc:
            last = number == len(lines) and not text.endswith("\n")
            reason = "truncated last line" if last else f"malformed JSON ({exc.msg})"
            result.issues.append(f"{where}: {reason}; frame skipped")
            continue
        if not isinstance(record, dict):
            result.issues.append(f"{where}: expected a JSON object; skipped")
            continue
        try:
            observations, issues = parse_detection_record(record, where, pitch, result.image_size, min_confidence)
        except (ValueError, TypeError, KeyError, IndexError, AttributeError, OverflowError) as exc:
            result.issues.append(f"{where}: {' '.join(str(exc).split()) or type(exc).__name__}; frame skipped")
            continue
        if result.image_size is None:
            result.image_size = (observations.width_px, observations.height_px)
        result.issues.extend(issues)
        if observations.frame_index in result.frames:
            result.issues.append(f"{where}: frame {observations.frame_index} repeated; the later record is used")
        result.frames[observations.frame_index] = observations
        if "frame_id" in record:
            result.frame_ids[observations.frame_index] = str(record["frame_id"])
        if record.get("mask"):
            try:
                result.mask_paths[observations.frame_index] = (path.parent / str(record["mask"])).resolve()
            except (ValueError, OSError) as exc:
                result.issues.append(f"{where}: mask path {str(record['mask'])[:40]!r}: {exc}; mask ignored")
    if not result.frames:
        raise InputError(path, "no usable detection record" if text.strip() else "empty file")
    unknown = sorted({issue.split("'")[1] for issue in result.issues if ": unknown line class '" in issue})
    if unknown and all(obs.is_empty for obs in result.frames.values()):
        raise InputError(path, f"no record has a usable detection: line class names such as '{unknown[0]}' are not "
                               f"SoccerNet classes (e.g. 'Side line top', 'Middle line', 'Circle central')")
    _report(path, result.issues)
    return result


MAX_ISSUES_SHOWN = 10  # issues logged one by one; the rest are summed up in one warning


def _report(path: Path, issues: list[str]) -> None:
    """Log the first issues one by one, then one line counting the rest by kind."""
    for issue in issues[:MAX_ISSUES_SHOWN]:
        log.warning(issue)
    rest = issues[MAX_ISSUES_SHOWN:]
    if rest:
        kinds: dict[str, int] = {}
        for issue in rest:
            kind = issue.split(": ", 1)[-1].split("'")[0].split(":")[0].strip()
            kinds[kind] = kinds.get(kind, 0) + 1
        common = ", ".join(f"{count} x '{kind}'" for kind, count in sorted(kinds.items(), key=lambda kv: -kv[1])[:3])
        log.warning("%s: %d more issues (%s); every issue is counted in the run summary", path, len(rest), common)


def detections_frame_range(path: str | Path) -> tuple[int, int]:
    """(first frame index, last + 1) of a detections file, without parsing its detections.

    Reads only each line's ``"frame"`` field (written first by :class:`DetectionsWriter`; other
    lines are parsed as JSON). Lines that are not records are ignored, as :func:`read_detections` does.

    Raises:
        InputError: the file is missing, unreadable or holds no record with a frame index.
    """
    path = Path(path)
    first, last = None, None
    try:
        with path.open(encoding="utf-8") as handle:
            for line in handle:
                frame = _frame_of_line(line)
                if frame is not None:
                    first = frame if first is None else min(first, frame)
                    last = frame if last is None else max(last, frame)
    except (OSError, UnicodeDecodeError) as exc:
        raise InputError(path, f"cannot read detections file: {exc}") from None
    if first is None:
        raise InputError(path, "no detection record with a frame index")
    return first, last + 1


def _frame_of_line(line: str) -> int | None:
    prefix = '{"frame": '
    if line.startswith(prefix):
        digits = line[len(prefix):len(prefix) + 12].split(",")[0].split("}")[0].strip()
        if digits.isdigit():
            return int(digits)
    try:
        record = json.loads(line)
    except json.JSONDecodeError:
        return None
    frame = record.get("frame") if isinstance(record, dict) else None
    return frame if isinstance(frame, int) and not isinstance(frame, bool) and frame >= 0 else None


def annotations_to_observations(lines_norm: dict[str, np.ndarray], frame_index: int, width_px: int,
                                height_px: int) -> FrameObservations:
    """SoccerNet line annotation (normalised) -> line observations in pixels ("Line/Goal unknown" dropped)."""
    scale = np.array([width_px - 1.0, height_px - 1.0])
    lines = {name: np.asarray(points, float) * scale for name, points in lines_norm.items() if name in LINE_CLASSES}
    return FrameObservations(frame_index, width_px, height_px, lines_px=lines)
