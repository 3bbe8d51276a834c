"""The global search's stages: which candidate focal points a shot whose camera is not known is searched at.

Used by :class:`~broadtrack_graph.track.reinit_policy.ReinitPolicy` (its module docstring says when
each stage runs); the positions and where their numbers come from are :mod:`broadtrack_graph.reinit.positions`'.
"""

from __future__ import annotations

from broadtrack_graph.reinit.positions import (
    CAMERA_KINDS,
    DEFAULT_TRIPOD_POSITIONS_W,
    FAR_MAIN_POSITIONS_W,
    NEAR_MAIN_POSITIONS_W,
)

MAIN_STAGES: tuple[tuple[str, tuple | None], ...] = (
    ("default positions", None),
    ("main camera further back", FAR_MAIN_POSITIONS_W),
    *((f"low gantry {p}", (p,)) for p in NEAR_MAIN_POSITIONS_W),
)
"""Stages that find the main camera (the default positions also hold the 16 m and behind-the-goal guesses)."""

KIND_STAGES: dict[str, tuple[str, tuple]] = {
    kind.name: (f"{kind.name} cameras", tuple(p for p in kind.positions_w if p not in DEFAULT_TRIPOD_POSITIONS_W.values()))
    for kind in CAMERA_KINDS[1:] if any(p not in DEFAULT_TRIPOD_POSITIONS_W.values() for p in kind.positions_w)
}
"""Per other camera kind: the stage that searches its positions the default search does not try."""

SEARCH_STAGES: tuple[tuple[str, tuple | None], ...] = MAIN_STAGES + tuple(KIND_STAGES.values())
"""The stages of a shot whose camera is not known yet, after the known cameras' positions."""


CERTAIN_CONFIDENCE = 0.9
"""A camera found this confident at a shot's start is not searched past (the later stages cannot do better by
the margin); below it, every stage is searched."""
