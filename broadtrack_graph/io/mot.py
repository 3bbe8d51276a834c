"""MOT-format tracking files: ``frame,id,x,y,w,h,conf,...`` per line (frame 1-based, box left, top, width, height in pixels).

Columns after ``conf`` (MOT's world x, y, z or class, visibility) are ignored. A
confidence of -1 (MOT's "not given") counts as 1. Blank lines and ``#`` comments are
skipped; a malformed line, a frame number below 1 or a NaN / empty box is reported
one line each and skipped. :func:`write_mot` writes the same format.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.jsonfile import read_text
from broadtrack_graph.types.player_boxes import PlayerBoxes


def read_mot(path: str | Path, image_size: tuple[int, int] | None = None) -> PlayerBoxes:
    """Read a MOT file into :class:`~broadtrack_graph.types.player_boxes.PlayerBoxes` (frame index = MOT frame - 1).

    Args:
        path: the file.
        image_size: (W, H) the boxes refer to (MOT files do not say), or None.

    Raises:
        InputError: missing or empty file.
    """
    path = Path(path)
    text = read_text(path, "MOT file")
    if not text.strip():
        raise InputError(path, "empty file")
    result = PlayerBoxes(source=str(path), kind="mot", image_size=image_size)
    rows: dict[int, list] = {}
    for number, line in enumerate(text.splitlines(), start=1):
        stripped = line.strip()
        if not stripped or stripped.startswith("#"):
            continue
        parts = [p.strip() for p in stripped.replace(";", ",").split(",")]
        try:
            if len(parts) < 6:
                raise ValueError(f"{len(parts)} fields, expected at least 6 (frame,id,x,y,w,h)")
            frame_f, track_f = float(parts[0]), float(parts[1])
            if not (frame_f.is_integer() and track_f.is_integer()):
                raise ValueError("frame and id must be integers")
            x, y, w, h = (float(v) for v in parts[2:6])
            conf = float(parts[6]) if len(parts) > 6 and parts[6] else 1.0
        except ValueError as exc:
            result.issues.append(f"{path}:{number}: malformed line ({exc}); skipped")
            continue
        if frame_f < 1:
            result.issues.append(f"{path}:{number}: frame {int(frame_f)} below 1 (MOT frames are 1-based); skipped")
            continue
        if not all(math.isfinite(v) for v in (x, y, w, h)) or w <= 0 or h <= 0:
            result.issues.append(f"{path}:{number}: box {[x, y, w, h]} is not finite or empty; skipped")
            continue
        conf = 1.0 if conf == -1 or not math.isfinite(conf) else conf
        rows.setdefault(int(frame_f), []).append((int(track_f), x, y, x + w, y + h, conf))
    for frame in sorted(rows):
        data = np.array(rows[frame], dtype=float)
        result.add_frame(frame - 1, None, data[:, 1:5], data[:, 0].astype(int), confidences=np.clip(data[:, 5], 0, 1))
    return result


def write_mot(path: str | Path, boxes: PlayerBoxes) -> None:
    """Write boxes as a MOT file (frame = index + 1; frames without an index are skipped)."""
    lines = []
    for frame in boxes.frames:
        if frame.frame_index is None:
            continue
        for tid, (x0, y0, x1, y1), conf in zip(frame.track_ids, frame.boxes_px, frame.confidences):
            lines.append(f"{frame.frame_index + 1},{int(tid)},{x0:.2f},{y0:.2f},{x1 - x0:.2f},{y1 - y0:.2f},{conf:.3f},-1,-1,-1")
    Path(path).write_text("\n".join(lines) + "\n", encoding="utf-8")
