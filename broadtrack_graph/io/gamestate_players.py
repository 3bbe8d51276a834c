"""Player boxes of a SoccerNet game-state ``Labels-GameState.json`` (object annotations with track ids, roles, teams).

An object annotation (``supercategory`` "object") has ``image_id``, ``track_id``,
``attributes`` {``role``, ``team``, ``jersey``} and ``bbox_image`` {``x``, ``y``, ``w``, ``h``}
(left, top, width, height in pixels). The frame id is the stem of the image's
``file_name`` and the frame index its position in the ``images`` list. Balls are not
players and are left out. Annotations naming an unknown image, without a usable box or
with a NaN box are reported one line each and skipped.
"""

from __future__ import annotations

import math
from pathlib import Path

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.jsonfile import read_json
from broadtrack_graph.types.player_boxes import NO_TRACK_ID, PlayerBoxes


def read_gamestate_players(path: str | Path) -> PlayerBoxes:
    """Read the player boxes of a game-state labels file.

    Returns:
        PlayerBoxes (kind "gamestate") with one frame per image that has a player box, in image order,
        and ``image_ids`` (frame id -> the file's image_id).

    Raises:
        InputError: not a game-state file.
    """
    path = Path(path)
    data = read_json(path)
    if not isinstance(data, dict) or not isinstance(data.get("images"), list) or not isinstance(data.get("annotations"), list):
        raise InputError(path, "not a game-state file: expected 'images' and 'annotations' lists")
    result = PlayerBoxes(source=str(path), kind="gamestate")
    frame_of: dict[str, tuple[int, str]] = {}
    for position, image in enumerate(data["images"]):
        try:
            frame_of[str(image["image_id"])] = (position, Path(str(image["file_name"])).stem)
        except (KeyError, TypeError):
            result.issues.append(f"{path}: image entry {position} without file_name/image_id; skipped")
            continue
        if result.image_size is None and "width" in image and "height" in image:
            result.image_size = (int(image["width"]), int(image["height"]))
    per_image: dict[str, list] = {}
    for number, annotation in enumerate(data["annotations"]):
        if not isinstance(annotation, dict) or annotation.get("supercategory") != "object":
            continue
        attributes = annotation.get("attributes") or {}
        role = attributes.get("role")
        if role == "ball":
            continue
        image_id = str(annotation.get("image_id"))
        where = f"{path}: annotation {annotation.get('id', number)}"
        if image_id not in frame_of:
            result.issues.append(f"{where}: unknown image_id {image_id}; skipped")
            continue
        box = annotation.get("bbox_image")
        try:
            x, y, w, h = (float(box[k]) for k in ("x", "y", "w", "h"))
        except (KeyError, TypeError, ValueError):
            result.issues.append(f"{where}: no usable bbox_image {{x, y, w, h}}; skipped")
            continue
        if not all(math.isfinite(v) for v in (x, y, w, h)) or w <= 0 or h <= 0:
            result.issues.append(f"{where}: box {[x, y, w, h]} is not finite or empty; skipped")
            continue
        try:
            track_id = int(annotation.get("track_id")) if annotation.get("track_id") is not None else NO_TRACK_ID
        except (TypeError, ValueError):
            track_id = NO_TRACK_ID
        per_image.setdefault(image_id, []).append((track_id, [x, y, x + w, y + h], role, attributes.get("team")))
    for image_id, (position, frame_id) in sorted(frame_of.items(), key=lambda item: item[1][0]):
        rows = per_image.get(image_id)
        if not rows:
            continue
        result.image_ids[frame_id] = image_id
        result.add_frame(position, frame_id, [r[1] for r in rows], [r[0] for r in rows], [r[2] for r in rows],
                         [r[3] for r in rows])
    return result
