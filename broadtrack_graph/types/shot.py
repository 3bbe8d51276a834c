"""A shot: a run of frames between two boundaries, its kind and its camera id.

Found by :mod:`broadtrack_graph.shots`, named by the tracker (:func:`place_shot`), written to
``shots.json`` by :mod:`broadtrack_graph.io.shots_file`. A pitch shot's kind is ``main`` (the main
camera), ``other-camera`` (another pitch camera: behind a goal, near a corner, ...) or ``pitch``
(a pitch view no camera was placed for); ``close-up`` and ``crowd`` shots have no camera. A shot read as another
view in which the tracker placed a camera anyway (its markings fix one) is a pitch shot: its ``views`` keep what the
frames were read as.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

MAIN_CAMERA_ID = "main"
"""Camera id of the main camera's shots."""

KIND_MAIN, KIND_OTHER_CAMERA, KIND_PITCH = "main", "other-camera", "pitch"
NO_PITCH_KINDS = ("close-up", "crowd")
SHOT_KINDS = (KIND_MAIN, KIND_OTHER_CAMERA, KIND_PITCH, *NO_PITCH_KINDS)
"""Kinds of a shot: a pitch camera's (main, another, or not placed) or a view with no pitch to fit."""


@dataclass
class Shot:
    """A run of frames between two boundaries.

    start, end: first frame index and one past the last (0-based, end exclusive).
    kind: one of :data:`SHOT_KINDS`: the majority view of its frames ("main" for a pitch view,
        "close-up", "crowd") until :func:`place_shot` names the pitch camera.
    camera_id: the pitch camera's id (set by the tracker), None for other views or when unknown.
    boundary: how it began: "start" (first frame of the input), "hard", "dissolve" or "view" (a view change).
    views: frames per view kind.
    """

    start: int
    end: int
    kind: str
    camera_id: str | None
    boundary: str = "start"
    views: dict = field(default_factory=dict)


def place_shot(shot: Shot, camera_id: str | None) -> Shot:
    """The shot with its pitch camera named (module docstring); no-pitch shots without a camera are returned as they
    are."""
    if shot.kind in NO_PITCH_KINDS and camera_id is None:
        return replace(shot, camera_id=None)
    if camera_id is None:
        return replace(shot, kind=KIND_PITCH, camera_id=None)
    kind = KIND_MAIN if camera_id == MAIN_CAMERA_ID else KIND_OTHER_CAMERA
    return replace(shot, kind=kind, camera_id=camera_id)
