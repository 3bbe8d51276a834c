"""Players on the pitch: ``players.jsonl`` (one line per box) and the SoccerNet game-state predictions file.

``players.jsonl``, one JSON object per player box and frame, flushed per frame::

    {"frame": 0, "frame_id": "000001", "track_id": 7, "box_px": [x0, y0, x1, y1],
     "role": "player", "team": "left",
     "x_m": 12.3, "y_m": -4.5, "std_m": [0.08, 0.21],
     "bottom_left_m": [x, y], "bottom_right_m": [x, y],
     "camera_status": "tracked", "reason": null}

Positions are the bottom middle of the box on the ground plane, metres, SoccerNet
pitch frame (origin centre spot, x to the right goal, +y to the near touchline);
``std_m`` the standard deviations of x and y (camera uncertainty and foot-point pixel
noise). ``x_m``, ``y_m``, ``std_m`` are null when the frame has no camera (then
``camera_status`` is the frame's status and ``reason`` says why) or the foot does not
reach the ground (``reason`` says why). ``track_id`` is -1 when the source gives none.

The predictions file (``<name>.json``) is what SoccerNet's game-state tooling reads:
``{"info": {...}, "predictions": [{"id", "image_id", "track_id", "supercategory": "object",
"category_id", "attributes": {"role", "team", "jersey"}, "bbox_image": {"x", "y",
"x_center", "y_center", "w", "h"}, "bbox_pitch": {"x_bottom_left", "y_bottom_left",
"x_bottom_middle", "y_bottom_middle", "x_bottom_right", "y_bottom_right"}}]}`` (pixels,
metres); only boxes with a position are listed.
"""

from __future__ import annotations

import json
import logging
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.jsonfile import read_text, write_json_atomic

log = logging.getLogger(__name__)

PLAYERS_FILE = "players.jsonl"
PREDICTIONS_FILE = "predictions-gamestate.json"
CATEGORY_IDS = {"player": 1, "goalkeeper": 2, "referee": 3, "ball": 4, "other": 5}
"""SoccerNet game-state category ids by role."""


def _num(value, digits: int = 4):
    if value is None:
        return None
    value = float(value)
    return round(value, digits) if np.isfinite(value) else None


def player_line(frame_index: int, frame_id: str, track_id: int, box_px, role, team, xy_m, std_m, left_m, right_m,
                status: str, reason: str | None) -> dict:
    """One ``players.jsonl`` object (see the module docstring); array arguments may hold NaN (written as null)."""
    has = xy_m is not None and np.isfinite(xy_m).all()
    return {
        "frame": int(frame_index), "frame_id": str(frame_id), "track_id": int(track_id),
        "box_px": [_num(v, 2) for v in box_px], "role": role, "team": team,
        "x_m": _num(xy_m[0]) if has else None, "y_m": _num(xy_m[1]) if has else None,
        "std_m": [_num(std_m[0]), _num(std_m[1])] if has and std_m is not None else None,
        "bottom_left_m": [_num(v) for v in left_m] if has and left_m is not None and np.isfinite(left_m).all() else None,
        "bottom_right_m": [_num(v) for v in right_m] if has and right_m is not None and np.isfinite(right_m).all() else None,
        "camera_status": status, "reason": reason,
    }


class PlayersWriter:
    """Append frames to ``players.jsonl``, one flush per frame (an interrupted run keeps what it wrote)."""

    def __init__(self, path: str | Path) -> None:
        self.path = Path(path)
        try:
            self.path.parent.mkdir(parents=True, exist_ok=True)
            self._handle = self.path.open("w", encoding="utf-8")
        except OSError as exc:
            raise InputError(self.path, f"cannot write: {exc.strerror or exc}") from None

    def write_frame(self, lines: list[dict]) -> None:
        if lines:
            self._handle.write("".join(json.dumps(line) + "\n" for line in lines))
            self._handle.flush()

    def close(self) -> None:
        self._handle.close()

    def __enter__(self) -> "PlayersWriter":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


@dataclass
class PlayerPositions:
    """``players.jsonl`` read back as arrays (one row per box).

    frame: (N,) frame indices; track_id: (N,) int (-1 unknown); xy_m: (N, 2) metres (NaN without position);
    std_m: (N, 2) metres (NaN when unknown); box_px: (N, 4) pixels; frame_ids, roles, teams, status, reasons: N entries.
    """

    frame: np.ndarray
    track_id: np.ndarray
    xy_m: np.ndarray
    std_m: np.ndarray
    box_px: np.ndarray
    frame_ids: list
    roles: list
    teams: list
    status: list
    reasons: list

    def __len__(self) -> int:
        return len(self.frame)

    @property
    def has_position(self) -> np.ndarray:
        return np.isfinite(self.xy_m).all(axis=1)


def positions_from_lines(lines: list[dict]) -> PlayerPositions:
    """Rows of ``players.jsonl`` objects as :class:`PlayerPositions`."""
    def arr(key, width):
        out = np.full((len(lines), width), np.nan)
        for i, line in enumerate(lines):
            value = line.get(key)
            if value is not None:
                out[i] = [np.nan if v is None else float(v) for v in value]
        return out

    xy = np.array([[np.nan if line.get(k) is None else float(line[k]) for k in ("x_m", "y_m")] for line in lines]).reshape(-1, 2)
    return PlayerPositions(
        frame=np.array([int(line["frame"]) for line in lines], dtype=int),
        track_id=np.array([int(line.get("track_id", -1)) for line in lines], dtype=int),
        xy_m=xy, std_m=arr("std_m", 2), box_px=arr("box_px", 4),
        frame_ids=[str(line.get("frame_id")) for line in lines], roles=[line.get("role") for line in lines],
        teams=[line.get("team") for line in lines], status=[line.get("camera_status") for line in lines],
        reasons=[line.get("reason") for line in lines],
    )


def read_players_file(path: str | Path) -> PlayerPositions:
    """Read ``players.jsonl`` (or the folder holding it); a truncated last line is skipped with a warning.

    Raises:
        InputError: missing file or a malformed line before the last.
    """
    path = Path(path)
    if path.is_dir():
        path = path / PLAYERS_FILE
    lines = read_text(path, "players file").split("\n")
    while lines and not lines[-1].strip():
        lines.pop()
    rows = []
    for number, text in enumerate(lines, start=1):
        if not text.strip():
            continue
        try:
            row = json.loads(text)
            int(row["frame"])
        except (json.JSONDecodeError, KeyError, TypeError, ValueError) as exc:
            if number == len(lines):
                log.warning("%s: line %d is truncated or malformed; skipped", path, number)
                continue
            raise InputError(path, f"line {number}: {exc}") from None
        rows.append(row)
    return positions_from_lines(rows)


def gamestate_prediction(line: dict, image_id: str) -> dict | None:
    """The game-state prediction of one ``players.jsonl`` object, or None when it has no position."""
    if line.get("x_m") is None:
        return None
    x0, y0, x1, y1 = line["box_px"]
    middle = (line["x_m"], line["y_m"])
    left = line.get("bottom_left_m") or middle
    right = line.get("bottom_right_m") or middle
    role = line.get("role") or "player"
    return {
        "id": f"{image_id}-{line['track_id']}-{round(x0)}-{round(y0)}", "image_id": str(image_id),
        "track_id": int(line["track_id"]), "supercategory": "object",
        "category_id": CATEGORY_IDS.get(role, CATEGORY_IDS["other"]),
        "attributes": {"role": role, "team": line.get("team"), "jersey": None},
        "bbox_image": {"x": x0, "y": y0, "x_center": round((x0 + x1) / 2, 2), "y_center": round((y0 + y1) / 2, 2),
                       "w": round(x1 - x0, 2), "h": round(y1 - y0, 2)},
        "bbox_pitch": {"x_bottom_left": left[0], "y_bottom_left": left[1],
                       "x_bottom_middle": middle[0], "y_bottom_middle": middle[1],
                       "x_bottom_right": right[0], "y_bottom_right": right[1]},
    }


def write_gamestate_predictions(path: str | Path, lines: list[dict], image_ids: dict[str, str] | None = None,
                                name: str = "broadtrack-graph") -> int:
    """Write the game-state predictions of ``players.jsonl`` objects; returns how many predictions.

    Args:
        path: the .json file (written atomically).
        lines: ``players.jsonl`` objects.
        image_ids: frame id -> image_id of the source's labels (default: the frame index + 1, as a string,
            the numbering of game-state files this project writes).
        name: stored under ``info``.
    """
    image_ids = image_ids or {}
    predictions = []
    for line in lines:
        image_id = image_ids.get(str(line["frame_id"]), str(int(line["frame"]) + 1))
        prediction = gamestate_prediction(line, image_id)
        if prediction is not None:
            predictions.append(prediction)
    write_json_atomic(path, {"info": {"version": "1.0", "name": name}, "predictions": predictions})
    return len(predictions)


def boxes_from_positions(positions: PlayerPositions, source: str = "players.jsonl"):
    """The boxes of a players file as :class:`~broadtrack_graph.types.player_boxes.PlayerBoxes` (to locate the same
    boxes through another run's cameras)."""
    from broadtrack_graph.types.player_boxes import PlayerBoxes

    out = PlayerBoxes(source=source, kind="players")
    for frame in np.unique(positions.frame):
        rows = np.flatnonzero(positions.frame == frame)
        out.add_frame(int(frame), positions.frame_ids[rows[0]], positions.box_px[rows], positions.track_id[rows],
                      [positions.roles[i] for i in rows], [positions.teams[i] for i in rows])
    return out
