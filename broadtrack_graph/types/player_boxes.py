"""Player boxes per frame, as one in-memory type (:class:`PlayerBoxes`), whatever their source.

The readers of each box format are :mod:`broadtrack_graph.io.player_boxes`'s; the project's own
detector gives boxes too (``Detections.player_boxes_px``): :meth:`PlayerBoxes.add_frame` collects
them while tracking. Bad boxes (NaN, empty) are reported one line each in ``issues`` and skipped.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

NO_TRACK_ID = -1
"""Track id of a box whose source gives none."""


@dataclass
class PlayerFrame:
    """The player boxes of one frame.

    frame_index: 0-based frame index in the clip, or None when only the frame id is known.
    frame_id: the frame's id (image stem, e.g. "000001"), or None when only the index is known.
    track_ids: (N,) int, :data:`NO_TRACK_ID` when unknown.
    boxes_px: (N, 4) [x0, y0, x1, y1] pixels (at the source's image size).
    roles: N strings ("player", "goalkeeper", "referee", ...) or None each.
    teams: N strings ("left", "right", ...) or None each.
    confidences: (N,) in [0, 1] (1 when not given).
    """

    frame_index: int | None
    frame_id: str | None
    track_ids: np.ndarray
    boxes_px: np.ndarray
    roles: list = field(default_factory=list)
    teams: list = field(default_factory=list)
    confidences: np.ndarray | None = None

    def __post_init__(self) -> None:
        self.boxes_px = np.asarray(self.boxes_px, dtype=float).reshape(-1, 4)
        n = len(self.boxes_px)
        self.track_ids = np.asarray(self.track_ids, dtype=int).reshape(n)
        self.roles = list(self.roles) if self.roles else [None] * n
        self.teams = list(self.teams) if self.teams else [None] * n
        self.confidences = np.ones(n) if self.confidences is None else np.asarray(self.confidences, float).reshape(n)
        if len(self.roles) != n or len(self.teams) != n:
            raise ValueError("roles and teams must have one entry per box")

    def __len__(self) -> int:
        return len(self.boxes_px)


@dataclass
class PlayerBoxes:
    """Player boxes of a clip.

    frames: list of :class:`PlayerFrame`, in source order (one per frame).
    source: the file read (or a description, e.g. "detector").
    kind: "gamestate", "mot", "detections" or "detector".
    image_size: (W, H) the boxes refer to, when the source says.
    issues: one line per skipped item.
    image_ids: frame id -> the source's image_id (game-state files), for writing predictions back.
    """

    frames: list[PlayerFrame] = field(default_factory=list)
    source: str = ""
    kind: str = ""
    image_size: tuple[int, int] | None = None
    issues: list[str] = field(default_factory=list)
    image_ids: dict[str, str] = field(default_factory=dict)

    def add_frame(self, frame_index: int | None, frame_id: str | None, boxes_px, track_ids=None, roles=None,
                  teams=None, confidences=None) -> None:
        """Append a frame (boxes (N, 4) [x0, y0, x1, y1] pixels); rows with NaN or empty boxes are reported and dropped."""
        boxes = np.asarray(boxes_px, dtype=float).reshape(-1, 4)
        n = len(boxes)
        ids = np.full(n, NO_TRACK_ID) if track_ids is None else np.asarray(track_ids, dtype=int).reshape(n)
        roles = list(roles) if roles is not None else [None] * n
        teams = list(teams) if teams is not None else [None] * n
        conf = np.ones(n) if confidences is None else np.asarray(confidences, dtype=float).reshape(n)
        good = valid_boxes(boxes)
        where = f"frame {frame_id if frame_id is not None else frame_index}"
        for i in np.flatnonzero(~good):
            self.issues.append(f"{self.source}: {where}: box {boxes[i].tolist()} is not finite or empty; skipped")
        keep = np.flatnonzero(good)
        self.frames.append(PlayerFrame(frame_index, frame_id, ids[keep], boxes[keep], [roles[i] for i in keep],
                                       [teams[i] for i in keep], conf[keep]))

    @property
    def box_count(self) -> int:
        return sum(len(f) for f in self.frames)

    def scaled(self, width_px: int, height_px: int) -> "PlayerBoxes":
        """The boxes at another image size (no change when the source size is unknown or equal)."""
        if self.image_size is None or tuple(self.image_size) == (width_px, height_px):
            return self
        sx, sy = width_px / self.image_size[0], height_px / self.image_size[1]
        scale = np.array([sx, sy, sx, sy])
        frames = [PlayerFrame(f.frame_index, f.frame_id, f.track_ids, f.boxes_px * scale, f.roles, f.teams,
                              f.confidences) for f in self.frames]
        return PlayerBoxes(frames, self.source, self.kind, (width_px, height_px), list(self.issues), dict(self.image_ids))


def valid_boxes(boxes_px: np.ndarray) -> np.ndarray:
    """(N,) bool: finite boxes with x1 > x0 and y1 > y0."""
    b = np.asarray(boxes_px, dtype=float).reshape(-1, 4)
    with np.errstate(invalid="ignore"):
        return np.isfinite(b).all(axis=1) & (b[:, 2] > b[:, 0]) & (b[:, 3] > b[:, 1])
