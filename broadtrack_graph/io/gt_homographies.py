"""Reads ground-truth ground-plane homographies per frame (``gt_homographies.json``).

The file (one per clip) holds::

    {"image_size": [W, H],
     "frames": [{"frame": 0, "frame_id": "000001", "H_world_to_image": [[...], [...], [...]]}, ...]}

``H_world_to_image`` (3, 3) maps pitch ground-plane metres ``(x, y, 1)`` in the SoccerNet frame
(origin at the centre spot, x towards the right goal, +y towards the near touchline) to image
pixels at ``image_size`` (divide by the third row). Other keys are kept as ``info``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.jsonfile import read_json


@dataclass
class GroundTruthHomographies:
    """Per-frame ground truth of one clip.

    homographies: frame index -> (3, 3) H_world_to_image (metres -> pixels at image_size).
    frame_ids: frame index -> frame id string, when given.
    image_size: (W, H) pixels.
    info: the file's other top-level keys (provenance), as read.
    """

    homographies: dict[int, np.ndarray]
    image_size: tuple[int, int]
    frame_ids: dict[int, str] = field(default_factory=dict)
    info: dict = field(default_factory=dict)


def read_gt_homographies(path: str | Path) -> GroundTruthHomographies:
    """Read a ``gt_homographies.json``.

    Raises:
        InputError: missing file, malformed JSON, no image size, or a frame whose matrix is not
            3x3 finite and invertible (one line naming the file and the frame).
    """
    path = Path(path)
    data = read_json(path)
    if not isinstance(data, dict) or not isinstance(data.get("frames"), list):
        raise InputError(path, "expected an object with a 'frames' list")
    size = data.get("image_size")
    try:
        width, height = int(size[0]), int(size[1])
    except (TypeError, ValueError, IndexError):
        raise InputError(path, f"'image_size' must be [W, H], got {size!r}") from None
    homographies: dict[int, np.ndarray] = {}
    frame_ids: dict[int, str] = {}
    for number, entry in enumerate(data["frames"]):
        frame = entry.get("frame", number) if isinstance(entry, dict) else None
        if not isinstance(frame, int) or frame < 0:
            raise InputError(path, f"frames[{number}]: 'frame' must be a non-negative integer")
        try:
            H = np.array(entry["H_world_to_image"], dtype=float)
        except (KeyError, TypeError, ValueError):
            raise InputError(path, f"frame {frame}: no numeric 'H_world_to_image'") from None
        if H.shape != (3, 3) or not np.isfinite(H).all() or abs(np.linalg.det(H)) < 1e-12:
            raise InputError(path, f"frame {frame}: 'H_world_to_image' must be a finite invertible 3x3 matrix")
        homographies[frame] = H
        if "frame_id" in entry:
            frame_ids[frame] = str(entry["frame_id"])
    if not homographies:
        raise InputError(path, "no frame")
    info = {k: v for k, v in data.items() if k not in ("frames", "image_size")}
    return GroundTruthHomographies(homographies, (width, height), frame_ids, info)
