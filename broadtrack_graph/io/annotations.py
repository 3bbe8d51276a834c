"""SoccerNet line annotations: per-image NNNNN.json files or one Labels-GameState.json.

In memory an annotation is ``{class name: (N, 2) float array}`` of coordinates
normalised to the image (0 = left/top edge, 1 = right/bottom edge); pixels are
``x * (W - 1), y * (H - 1)`` (SoccerNet's rule). Class names are stripped of
SoccerNet's trailing spaces on reading.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.pitch import ALL_ANNOTATION_CLASSES
from broadtrack_graph.io.jsonfile import read_json, write_json_atomic

GAMESTATE_FILE = "Labels-GameState.json"

LineAnnotation = dict[str, np.ndarray]


@dataclass
class AnnotationSet:
    """Annotations of a set of frames.

    frames: frame id -> annotation (normalised coordinates).
    errors: frame id -> one-line message, for frames whose file could not be used.
    image_sizes: frame id -> (width, height) when the source states it (game-state files).
    """

    frames: dict[str, LineAnnotation] = field(default_factory=dict)
    errors: dict[str, str] = field(default_factory=dict)
    image_sizes: dict[str, tuple[int, int]] = field(default_factory=dict)

    def no_frames_reason(self) -> str:
        """Why a set without frames cannot be used, in one line: the unreadable files' count and the first's error."""
        if not self.errors:
            return "no usable annotation file"
        first = self.errors[min(self.errors)]
        return f"no usable annotation file ({len(self.errors)} unreadable, the first: {first})"


def parse_line_annotation(data, source: str | Path) -> LineAnnotation:
    """Validate one ``{class: [{"x":..,"y":..}, ...]}`` object.

    Raises:
        InputError: not an object, an unknown class name, a point without finite x and y.
    """
    if not isinstance(data, dict):
        raise InputError(source, f"expected a JSON object of line classes, got {type(data).__name__}")
    lines: LineAnnotation = {}
    for raw_name, points in data.items():
        name = str(raw_name).strip()
        if name not in ALL_ANNOTATION_CLASSES:
            raise InputError(source, f"unknown line class '{raw_name}'")
        if not isinstance(points, list):
            raise InputError(source, f"class '{name}': expected a list of points")
        coords = []
        for point in points:
            try:
                x, y = float(point["x"]), float(point["y"])
            except (TypeError, KeyError, ValueError):
                raise InputError(source, f"class '{name}': point without numeric x and y: {point!r}") from None
            if not (math.isfinite(x) and math.isfinite(y)):
                raise InputError(source, f"class '{name}': non-finite point {point!r}")
            coords.append((x, y))
        if coords:  # SoccerNet drops classes with no points
            lines[name] = np.asarray(coords, dtype=float)
    return lines


def read_annotation_file(path: str | Path) -> LineAnnotation:
    """Read one per-image annotation file (raises InputError naming the file)."""
    return parse_line_annotation(read_json(path), path)


def read_annotations(source: str | Path) -> AnnotationSet:
    """Read a folder of NNNNN.json files, a Labels-GameState.json, or a folder holding one.

    A file that cannot be used is recorded in ``errors`` (one line naming it) and
    skipped; the other frames are read.

    Raises:
        InputError: the source does not exist or holds no annotation file.
    """
    source = Path(source)
    if source.is_dir() and (source / GAMESTATE_FILE).is_file():
        return read_gamestate_annotations(source / GAMESTATE_FILE)
    if source.is_file():
        return read_gamestate_annotations(source)
    if not source.is_dir():
        raise InputError(source, "annotation folder or file not found")
    result = AnnotationSet()
    files = sorted(p for p in source.iterdir() if p.suffix == ".json" and not p.name.startswith("camera_"))
    if not files:
        raise InputError(source, "no annotation .json files in folder")
    for path in files:
        frame_id = path.stem
        try:
            result.frames[frame_id] = read_annotation_file(path)
        except InputError as exc:
            result.errors[frame_id] = str(exc)
    return result


def read_gamestate_annotations(path: str | Path) -> AnnotationSet:
    """Pitch line annotations of a SoccerNet game-state Labels-GameState.json.

    Frame ids are the image file stems (``000001`` for ``000001.jpg``). Only images
    with a pitch annotation are returned.
    """
    path = Path(path)
    data = read_json(path)
    if not isinstance(data, dict) or not isinstance(data.get("images"), list) or not isinstance(data.get("annotations"), list):
        raise InputError(path, "not a game-state file: expected 'images' and 'annotations' lists")
    result = AnnotationSet()
    id_to_frame = {}
    for image in data["images"]:
        try:
            frame_id = Path(image["file_name"]).stem
            id_to_frame[str(image["image_id"])] = frame_id
        except (KeyError, TypeError):
            raise InputError(path, f"image entry without file_name/image_id: {image!r}"[:200]) from None
        if "width" in image and "height" in image:
            result.image_sizes[frame_id] = (int(image["width"]), int(image["height"]))
    for annotation in data["annotations"]:
        if not isinstance(annotation, dict) or annotation.get("supercategory") != "pitch":
            continue
        frame_id = id_to_frame.get(str(annotation.get("image_id")))
        if frame_id is None:
            result.errors[str(annotation.get("image_id"))] = f"{path}: pitch annotation for unknown image_id {annotation.get('image_id')}"
            continue
        try:
            result.frames[frame_id] = parse_line_annotation(annotation.get("lines", {}), f"{path} (image {frame_id})")
        except InputError as exc:
            result.errors[frame_id] = str(exc)
    return result


def annotation_to_pixels(lines: LineAnnotation, width_px: int, height_px: int) -> LineAnnotation:
    """Normalised -> pixel coordinates with SoccerNet's ``x * (W - 1), y * (H - 1)``."""
    scale = np.array([width_px - 1, height_px - 1], dtype=float)
    return {name: points * scale for name, points in lines.items()}


def annotation_from_pixels(lines_px: LineAnnotation, width_px: int, height_px: int) -> LineAnnotation:
    """Pixel -> normalised coordinates (inverse of :func:`annotation_to_pixels`)."""
    scale = np.array([width_px - 1, height_px - 1], dtype=float)
    return {name: np.asarray(points, dtype=float) / scale for name, points in lines_px.items()}


def annotation_to_json(lines: LineAnnotation) -> dict:
    """In-memory annotation -> SoccerNet JSON object (normalised coordinates)."""
    return {
        name: [{"x": float(x), "y": float(y)} for x, y in np.asarray(points, dtype=float)]
        for name, points in lines.items()
        if len(points)
    }


def write_annotation_file(path: str | Path, lines: LineAnnotation) -> None:
    """Write one per-image NNNNN.json (normalised coordinates)."""
    write_json_atomic(path, annotation_to_json(lines))


def write_gamestate_labels(
    path: str | Path,
    frames: dict[str, LineAnnotation | None],
    width_px: int,
    height_px: int,
    image_extension: str = ".jpg",
    sequence_name: str = "synthetic",
    extra_annotations: list[dict] | None = None,
) -> None:
    """Write a Labels-GameState.json holding the pitch line annotations of a clip.

    Args:
        frames: frame id (image file stem, e.g. ``"000001"``) -> annotation, in clip order; None for
            an image without a pitch annotation (listed with ``has_labeled_pitch: false``).
        extra_annotations: further annotation objects (e.g. player boxes) appended as they are.
    """
    images, annotations = [], []
    for index, (frame_id, lines) in enumerate(frames.items(), start=1):
        image_id = str(index)
        images.append({
            "file_name": f"{frame_id}{image_extension}", "image_id": image_id, "width": int(width_px),
            "height": int(height_px), "is_labeled": True, "has_labeled_pitch": lines is not None,
            "has_labeled_camera": True,
        })
        if lines is None:
            continue
        annotations.append({
            "id": f"pitch-{image_id}", "image_id": image_id, "category_id": 5, "supercategory": "pitch",
            "lines": annotation_to_json(lines),
        })
    data = {
        "info": {"version": "1.0", "name": sequence_name, "im_dir": "img1", "seq_length": len(images), "im_ext": image_extension},
        "images": images,
        "annotations": annotations + list(extra_annotations or []),
        "categories": [{"supercategory": "pitch", "id": 5, "name": "pitch", "lines": list(ALL_ANNOTATION_CLASSES[:26])}],
    }
    write_json_atomic(path, data)
