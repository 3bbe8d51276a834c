"""Reads the per-frame keypoint predictions of No Bells Just Whistles (NBJW) / PnLCalib.

Their inference scripts write one JSON file per image (often inside a zip archive), named
``<clip>-IMG_<n>.json`` for TS-WorldCup or ``<n>.json`` elsewhere, holding a JSON object keyed by
keypoint number (a string, "1" to "73") with ``{"x": .., "y": .., "p": ..}``: the image position,
normalised by the image size (pixel = x * W, y * H) unless written in pixels, and the heatmap
peak probability. Some versions write a two-element list ``[keypoints, lines]`` instead; the
first element is read. Line entries (``x_1``, ``y_1``, ...) and keypoints without ``x``/``y``
are ignored.

The keypoint numbering (public, from the NBJW release) is held in :data:`NBJW_KEYPOINTS_W`,
converted to the SoccerNet frame: origin at the centre spot, x towards the right goal, +y
towards the near touchline, z down (the NBJW table has its origin at the far-left corner
flag, y from the far touchline, so x_sn = x - 52.5, y_sn = y - 34). Numbers 1-57 are the
network's keypoints (12, 15, 16, 19: the crossbar ends, z = -2.44 m); 58-73 are the
auxiliary points NBJW adds from line intersections. One deliberate difference: number 52
(the centre circle meets the halfway line's perpendicular through the centre spot, right
side) is at x = +9.15 m here, the circle's radius; the published table lists 9.0.
"""

from __future__ import annotations

import json
import re
import zipfile
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from broadtrack_graph.errors import InputError
from broadtrack_graph.types.observations import FrameObservations, KeypointObservations

NBJW_KEYPOINTS_W: dict[int, tuple[float, float, float]] = {
    # corners, touchline ends of the halfway line, penalty and goal areas (far side first)
    1: (-52.5, -34.0, 0.0), 2: (0.0, -34.0, 0.0), 3: (52.5, -34.0, 0.0), 4: (-52.5, -20.16, 0.0),
    5: (-36.0, -20.16, 0.0), 6: (36.0, -20.16, 0.0), 7: (52.5, -20.16, 0.0), 8: (-52.5, -9.16, 0.0),
    9: (-47.0, -9.16, 0.0), 10: (47.0, -9.16, 0.0), 11: (52.5, -9.16, 0.0), 12: (-52.5, -3.66, -2.44),
    13: (-52.5, -3.66, 0.0), 14: (52.5, -3.66, 0.0), 15: (52.5, -3.66, -2.44), 16: (-52.5, 3.66, -2.44),
    17: (-52.5, 3.66, 0.0), 18: (52.5, 3.66, 0.0), 19: (52.5, 3.66, -2.44), 20: (-52.5, 9.16, 0.0),
    21: (-47.0, 9.16, 0.0), 22: (47.0, 9.16, 0.0), 23: (52.5, 9.16, 0.0), 24: (-52.5, 20.16, 0.0),
    25: (-36.0, 20.16, 0.0), 26: (36.0, 20.16, 0.0), 27: (52.5, 20.16, 0.0), 28: (-52.5, 34.0, 0.0),
    29: (0.0, 34.0, 0.0), 30: (52.5, 34.0, 0.0),
    # penalty arcs, centre circle and their tangent / crossing points
    31: (-36.0, -7.32, 0.0), 32: (0.0, -9.15, 0.0), 33: (36.0, -7.32, 0.0), 34: (-36.0, 7.31, 0.0),
    35: (0.0, 9.15, 0.0), 36: (36.0, 7.31, 0.0), 37: (-32.51, -1.71, 0.0), 38: (-8.82, -2.47, 0.0),
    39: (8.81, -2.47, 0.0), 40: (32.5, -1.71, 0.0), 41: (-32.51, 1.7, 0.0), 42: (-8.82, 2.46, 0.0),
    43: (8.81, 2.46, 0.0), 44: (32.5, 1.7, 0.0), 45: (-41.5, 0.0, 0.0), 46: (-36.0, 0.0, 0.0),
    47: (-32.35, 0.0, 0.0), 48: (-6.47, -6.47, 0.0), 49: (6.47, -6.47, 0.0), 50: (-9.15, 0.0, 0.0),
    51: (0.0, 0.0, 0.0), 52: (9.15, 0.0, 0.0), 53: (-6.47, 6.47, 0.0), 54: (6.47, 6.47, 0.0),
    55: (32.35, 0.0, 0.0), 56: (36.0, 0.0, 0.0), 57: (41.5, 0.0, 0.0),
    # auxiliary intersections
    58: (-47.0, -34.0, 0.0), 59: (-36.0, -34.0, 0.0), 60: (36.0, -34.0, 0.0), 61: (47.0, -34.0, 0.0),
    62: (-47.0, -20.16, 0.0), 63: (47.0, -20.16, 0.0), 64: (-36.0, -9.16, 0.0), 65: (36.0, -9.16, 0.0),
    66: (-36.0, 9.16, 0.0), 67: (36.0, 9.16, 0.0), 68: (-47.0, 20.16, 0.0), 69: (47.0, 20.16, 0.0),
    70: (-47.0, 34.0, 0.0), 71: (-36.0, 34.0, 0.0), 72: (36.0, 34.0, 0.0), 73: (47.0, 34.0, 0.0),
}
"""NBJW keypoint number -> pitch position (metres, SoccerNet frame, z down)."""

_NUMBER = re.compile(r"(\d+)(?!.*\d)")


@dataclass
class NbjwPredictions:
    """Predictions of one clip read from a folder or zip.

    frames: one FrameObservations per file, frame index = position in numeric order.
    frame_ids: frame index -> file stem.
    keypoint_ids: frame index -> NBJW numbers of the kept keypoints (same order as the observations).
    issues: one line per skipped keypoint or file, naming the file.
    """

    frames: list[FrameObservations] = field(default_factory=list)
    frame_ids: dict[int, str] = field(default_factory=dict)
    keypoint_ids: dict[int, list[int]] = field(default_factory=dict)
    issues: list[str] = field(default_factory=list)


def _members(source: Path) -> list[tuple[str, callable]]:
    """(name, reader) per JSON file in a folder or zip archive."""
    if source.is_dir():
        return [(p.name, p.read_text) for p in source.iterdir() if p.suffix.lower() == ".json"]
    if source.is_file() and zipfile.is_zipfile(source):
        archive = zipfile.ZipFile(source)
        return [(name, lambda name=name: archive.read(name).decode("utf-8")) for name in archive.namelist()
                if name.lower().endswith(".json") and not name.endswith("/")]
    raise InputError(source, "not a folder or zip archive of NBJW prediction files")


def _clip_of(stem: str) -> str:
    """The clip part of a file stem: everything before a trailing ``IMG_<n>`` / number."""
    return re.sub(r"[-_]?(IMG_)?\d+$", "", stem)


def read_nbjw_predictions(source: str | Path, width_px: int, height_px: int, clip: str | None = None,
                          units: str = "normalized", min_probability: float = 0.0) -> NbjwPredictions:
    """Read NBJW / PnLCalib per-frame keypoint predictions into observations (pixels).

    Args:
        source: folder or zip archive of per-frame JSON files.
        width_px, height_px: size of the images the predictions are for (the output pixels).
        clip: keep only the files of this clip (file stem without its frame number); required
            when the source holds several clips.
        units: "normalized" (x, y in [0, 1] of the image) or "px".
        min_probability: keypoints with a lower ``p`` are skipped.

    Raises:
        InputError: no readable file, or several clips and no ``clip``.
    """
    source = Path(source)
    if units not in ("normalized", "px"):
        raise InputError(source, f"units must be 'normalized' or 'px', got {units!r}")
    members = [m for m in _members(source) if _NUMBER.search(Path(m[0]).stem)]
    clips = sorted({_clip_of(Path(name).stem) for name, _ in members})
    if clip is not None:
        members = [m for m in members if _clip_of(Path(m[0]).stem) == clip]
    elif len(clips) > 1:
        raise InputError(source, f"holds {len(clips)} clips ({', '.join(clips[:3])}, ...); choose one with --clip")
    if not members:
        raise InputError(source, "no numbered prediction file (.json)" + (f" for clip '{clip}'" if clip else ""))
    members.sort(key=lambda m: int(_NUMBER.search(Path(m[0]).stem).group(1)))
    scale = np.array([width_px, height_px], float) if units == "normalized" else np.ones(2)
    result = NbjwPredictions()
    for index, (name, read) in enumerate(members):
        where = f"{source}/{name}" if source.is_dir() else f"{source}:{name}"
        try:
            data = json.loads(read())
        except (json.JSONDecodeError, UnicodeDecodeError, OSError) as exc:
            result.issues.append(f"{where}: cannot read ({exc}); frame left without keypoints")
            data = {}
        if isinstance(data, list) and data and isinstance(data[0], dict):
            data = data[0]
        if not isinstance(data, dict):
            result.issues.append(f"{where}: expected an object of keypoints; frame left without keypoints")
            data = {}
        uv, world, prob, ids = [], [], [], []
        for key, entry in data.items():
            if not isinstance(entry, dict) or "x" not in entry or "y" not in entry:
                continue
            try:
                number = int(key)
            except ValueError:
                number = None
            if number not in NBJW_KEYPOINTS_W:
                result.issues.append(f"{where}: unknown keypoint number {key!r}; skipped")
                continue
            try:
                xy = np.array([float(entry["x"]), float(entry["y"])]) * scale
                p = float(entry.get("p", 1.0))
            except (TypeError, ValueError):
                result.issues.append(f"{where}: keypoint {number}: non-numeric x/y/p; skipped")
                continue
            if not (np.isfinite(xy).all() and np.isfinite(p)):
                result.issues.append(f"{where}: keypoint {number}: non-finite value; skipped")
                continue
            if not (0 <= xy[0] <= width_px - 1 and 0 <= xy[1] <= height_px - 1):
                continue  # NBJW may place line intersections outside the image; the tracker wants visible points
            if p < min_probability:
                continue
            uv.append(xy)
            world.append(NBJW_KEYPOINTS_W[number])
            prob.append(min(max(p, 0.0), 1.0))
            ids.append(number)
        keypoints = None
        if uv:
            keypoints = KeypointObservations(np.array(uv), np.array(world, float), np.array(prob), [""] * len(uv))
        result.frames.append(FrameObservations(index, width_px, height_px, keypoints=keypoints))
        result.frame_ids[index] = Path(name).stem
        result.keypoint_ids[index] = ids
    return result
