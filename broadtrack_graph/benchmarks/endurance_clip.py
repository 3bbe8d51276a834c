"""The endurance clip: a rendered segment played forwards, backwards, forwards... as a folder of
numbered images (symbolic links to the segment's JPEGs), so a long clip keeps an exact ground truth.
"""

from __future__ import annotations

import json
import os
import shutil
from pathlib import Path

CLIP_INFO = "endurance_clip.json"
"""Marker of an assembled endurance clip folder (segment, frame count): reused when it matches."""


def pingpong_index(frame_index: int, unique_frames: int) -> int:
    """Index in the rendered segment of a frame of the endurance clip (forwards, backwards, ...).

    Frames 0..U-1 show the segment, U..2U-3 show it backwards (U-2 down to 1), then 2U-2
    starts again at 0: the period is 2U-2, and consecutive frames are always neighbours.

    Args:
        frame_index: 0-based frame of the endurance clip.
        unique_frames: U, frames of the segment (>= 1).
    """
    if unique_frames < 1:
        raise ValueError(f"unique_frames must be >= 1, got {unique_frames}")
    if unique_frames == 1:
        return 0
    period = 2 * unique_frames - 2
    phase = int(frame_index) % period
    return phase if phase < unique_frames else period - phase


def endurance_frame_id(frame_index: int) -> str:
    """Image stem of a frame of the endurance clip: 0 -> "000001" (SoccerNet's 1-based, 6 digits)."""
    return f"{frame_index + 1:06d}"


def ensure_endurance_clip(segment: Path, folder: Path, frames: int, unique_frames: int) -> tuple[Path, bool]:
    """The ``frames``-frame image folder playing ``segment``'s img1/ back and forth (built or reused).

    Returns:
        (folder, True when it was built now).
    """
    wanted = {"segment": str(segment.resolve()), "frames": int(frames), "unique_frames": int(unique_frames)}
    info_path = folder / CLIP_INFO
    if info_path.is_file():
        try:
            if json.loads(info_path.read_text(encoding="utf-8")) == wanted:
                return folder, False
        except (OSError, json.JSONDecodeError):
            pass
    if folder.exists():
        shutil.rmtree(folder)
    folder.mkdir(parents=True)
    images = segment.resolve() / "img1"
    for k in range(frames):
        source = images / f"{endurance_frame_id(pingpong_index(k, unique_frames))}.jpg"
        os.symlink(source, folder / f"{endurance_frame_id(k)}.jpg")
    info_path.write_text(json.dumps(wanted), encoding="utf-8")
    return folder, True
