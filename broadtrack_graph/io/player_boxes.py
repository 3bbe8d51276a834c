"""Read player boxes from any source into one in-memory type (:class:`~broadtrack_graph.types.player_boxes.PlayerBoxes`).

:func:`read_player_boxes` picks the reader by what the path is:

* a ``Labels-GameState.json`` (or a folder holding one): SoccerNet game-state image
  boxes with track ids, roles and teams (:mod:`broadtrack_graph.io.gamestate_players`);
* a ``.txt`` / ``.csv`` file: MOT format ``frame,id,x,y,w,h,conf,...`` with 1-based
  frames (:mod:`broadtrack_graph.io.mot`);
* a ``.jsonl`` file: the ``players`` boxes of a detections file
  (:mod:`broadtrack_graph.io.detections`; no track ids).

The project's own detector gives boxes too (``Detections.player_boxes_px``):
:meth:`PlayerBoxes.add_frame` collects them while tracking.

Bad input is reported one line each in ``issues`` and skipped (NaN or empty boxes,
malformed lines, frame numbers below the first frame); only a missing, empty or
unreadable file is an error (InputError).
"""

from __future__ import annotations

import logging
from pathlib import Path

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.annotations import GAMESTATE_FILE
from broadtrack_graph.io.detections import read_detections
from broadtrack_graph.io.gamestate_players import read_gamestate_players
from broadtrack_graph.io.mot import read_mot
from broadtrack_graph.types.player_boxes import PlayerBoxes

log = logging.getLogger(__name__)

def read_player_boxes(path: str | Path, image_size: tuple[int, int] | None = None) -> PlayerBoxes:
    """Read player boxes from a game-state labels file, a MOT file or a detections file (see the module docstring).

    Args:
        path: the file (or a game-state sequence folder).
        image_size: (W, H) of the boxes when the file does not say (MOT files never do).

    Raises:
        InputError: missing, empty or unreadable file, or no usable box.
    """
    path = Path(path)
    if path.is_dir():
        if not (path / GAMESTATE_FILE).is_file():
            raise InputError(path, f"folder without {GAMESTATE_FILE}; give a box file")
        path = path / GAMESTATE_FILE
    if not path.is_file():
        raise InputError(path, "player box file not found")
    suffix = path.suffix.lower()
    if suffix == ".json":
        boxes = read_gamestate_players(path)
    elif suffix in (".txt", ".csv"):
        boxes = read_mot(path, image_size)
    elif suffix == ".jsonl":
        boxes = _read_detection_players(path, image_size)
    else:
        raise InputError(path, "unknown player box format (expected Labels-GameState .json, MOT .txt/.csv or "
                               "detections .jsonl)")
    if not boxes.box_count:
        raise InputError(path, "no usable player box")
    for issue in boxes.issues:
        log.warning(issue)
    return boxes


def _read_detection_players(path: Path, image_size) -> PlayerBoxes:
    detections = read_detections(path, image_size=image_size)
    result = PlayerBoxes(source=str(path), kind="detections", image_size=detections.image_size,
                         issues=list(detections.issues))
    for index in sorted(detections.frames):
        observations = detections.frames[index]
        boxes = observations.player_boxes_px
        if boxes is None:
            continue
        result.add_frame(index, detections.frame_ids.get(index), boxes)
    return result
