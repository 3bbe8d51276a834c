"""The global search's stages: which candidate focal points a shot whose camera is not known is searched at.

Used by :class:`~broadtrack_graph.track.reinit_policy.ReinitPolicy` (its module docstring says when
each stage runs); the positions and where their numbers come from are :mod:`broadtrack_graph.reinit.positions`'.
A search reads at most two stages. Where the court model looks at the marking map it places a camera wherever it
stands (a returning camera too, named by where it stands), so a shot whose camera is known is searched only at that
camera's position (a known camera lost mid-shot), and a new shot only at the known cameras' positions, for a
returning camera alone: a known camera's view whose markings do not fix a camera from nothing (a zoomed view of a
circle's arc beside a touchline) fixes it on its known tripod, where the court model does not place it. The default
positions are searched without the court model, and on labelled detections (no map).
"""

from __future__ import annotations

from typing import NamedTuple

from broadtrack_graph.reinit.positions import MAIN_KIND, camera_kind

DEFAULT_STAGE: tuple[str, None] = ("default positions", None)
"""The stage at the default positions (:data:`~broadtrack_graph.reinit.positions.DEFAULT_TRIPOD_POSITIONS_W`: the
main camera's, the 16 m lines', behind a goal; the search's own positions when none are given)."""

KNOWN_CAMERAS = "known cameras"
"""The label of the stage that searches the known cameras' positions."""


class SearchPlan(NamedTuple):
    """One search's stages, (label, positions) in order, whether it is a new shot's search on a marking map (read
    until a camera is certain), and whether only a returning camera is kept (:func:`search_plan`)."""

    stages: list
    new_shot: bool = False
    returning_only: bool = False


def search_plan(known_positions: dict, camera_id: str | None, search_positions, with_map: bool,
                held_trusted: bool = False, court_looks: bool = False) -> SearchPlan:
    """The stages of one search (the policy's module docstring says why).

    Args:
        known_positions: camera id -> (3,) position of the cameras known so far (metres).
        camera_id: the shot's camera id, None when the shot's camera is not known.
        search_positions: the run's given candidate positions (searched alone), or None.
        with_map: the frame has a marking map (a new shot's search on it reads its stages until a camera is
            certain).
        held_trusted: the shot's camera holds a trusted chain (its frames are being written), dipping under the
            threshold.
        court_looks: the court model looks at the frame's marking map: the shot's own camera's position alone (a
            new shot's plan: the known cameras', ``returning_only``: only a known camera found at its own position
            is kept).
    """
    if search_positions is not None:
        return SearchPlan([("the given positions", search_positions)])
    court_places = with_map and court_looks  # a new shot's camera, a returning one's too
    if camera_id is not None and camera_id in known_positions:
        # Mid-shot: the camera has not moved; its own position, then, for a main camera whose chain is not trusted,
        # the default positions (they guard against a wrong first camera's position). A trusted chain's camera
        # stands where its confident frames put it: its own position alone.
        own_position = tuple(known_positions[camera_id])
        own = [(f"camera {camera_id}", [own_position])]
        if not court_places and not held_trusted and camera_kind(own_position)[0] == MAIN_KIND:
            own.append(DEFAULT_STAGE)
        return SearchPlan(own)
    known = [tuple(p) for p in known_positions.values()]
    first = [(KNOWN_CAMERAS, known)] if known else []
    if court_places:
        return SearchPlan(first, new_shot=True, returning_only=True)
    return SearchPlan(first + [DEFAULT_STAGE], new_shot=with_map)
