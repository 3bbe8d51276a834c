"""The global search's stages: which candidate focal points a shot whose camera is not known is searched at.

Used by :class:`~broadtrack_graph.track.reinit_policy.ReinitPolicy` (its module docstring says when
each stage runs); the positions and where their numbers come from are :mod:`broadtrack_graph.reinit.positions`'.
"""

from __future__ import annotations

from typing import NamedTuple

from broadtrack_graph.reinit.positions import (
    CAMERA_KINDS,
    DEFAULT_TRIPOD_POSITIONS_W,
    FAR_MAIN_POSITIONS_W,
    MAIN_KIND,
    NEAR_MAIN_POSITIONS_W,
    camera_kind,
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


KNOWN_CAMERAS = "known cameras"
"""The label of the stage that searches the known cameras' positions."""

class SearchPlan(NamedTuple):
    """One search's stages: (label, positions) in order; how many of the first stages are the likely ones (their
    best camera wins by any amount; a later stage's must be confident and better by the margin); and whether it is a
    new shot's search on a marking map (read until a camera is certain)."""

    stages: list
    likely: int
    new_shot: bool = False


def search_plan(known_positions: dict, camera_id: str | None, search_positions, with_map: bool,
                shot_start_confidences: dict[str, float] | None = None, held_trusted: bool = False,
                all_places: bool = True) -> SearchPlan:
    """The stages of one search (the policy's module docstring says why).

    Args:
        known_positions: camera id -> (3,) position of the cameras known so far (metres).
        camera_id: the shot's camera id, None when the shot's camera is not known.
        search_positions: the run's given candidate positions (searched alone), or None.
        with_map: the frame has a marking map (without one, the labelled search is cheap: the default stage only).
        shot_start_confidences: for a shot searched before (:func:`retry_plan`), stage label -> the confidence of the
            camera its first search found there; None: the shot's first search.
        held_trusted: the shot's camera holds a trusted chain (its frames are being written), dipping under the
            threshold.
        all_places: on a marking map, every stage of :data:`SEARCH_STAGES` (``TrackingConfig.search_all_places``);
            else its first (the default positions) alone, and a known camera at its own position (and the default
            positions, for a main camera).
    """
    if search_positions is not None:
        return SearchPlan([("the given positions", search_positions)], 1)
    if camera_id is not None and camera_id in known_positions:
        # Mid-shot: the camera has not moved; its own position, then its kind's stage (the main camera's default
        # stage guards against a wrong first camera's position) while the chain is not trusted. A trusted chain's
        # camera stands where its confident frames put it: its own position alone.
        own_position = tuple(known_positions[camera_id])
        if held_trusted:
            return SearchPlan([(f"camera {camera_id}", [own_position])], 1)
        kind, _ = camera_kind(own_position)
        if kind == MAIN_KIND:
            own = list(MAIN_STAGES[:1])
        elif kind in KIND_STAGES and (all_places or not with_map):
            own = [KIND_STAGES[kind]]
        else:
            own = []
        return SearchPlan([(f"camera {camera_id}", [own_position])] + own, 2)
    known = [tuple(p) for p in known_positions.values()]
    first = [(KNOWN_CAMERAS, known)] if known else []
    if not with_map:
        return SearchPlan(first + list(SEARCH_STAGES[:1]), len(first) + 1)
    plan = SearchPlan(first + list(SEARCH_STAGES if all_places else SEARCH_STAGES[:1]), len(first) + 1, new_shot=True)
    return plan if shot_start_confidences is None else retry_plan(plan, shot_start_confidences)


def retry_plan(plan: SearchPlan, shot_start_confidences: dict[str, float]) -> SearchPlan:
    """A new shot's plan cut to a later search of the shot: its likely stages (the known cameras', the default
    positions) and the one other stage whose camera the shot's first search scored best, if any.

    The search at a shot's start read every stage and found no camera to trust: searching all of them again costs as
    much (a stage is about a tenth of a second to a second), so the shot's later searches, on frames that may show
    more, try the stages that were nearest (the shot's budget, :mod:`~broadtrack_graph.track.search_budget`).

    Args:
        plan: the new shot's full plan (:func:`search_plan`, ``new_shot``).
        shot_start_confidences: stage label -> the confidence of the camera the shot's first search found there (a
            stage that found none is missing).
    """
    others = [(shot_start_confidences[label], k, label) for k, (label, _) in enumerate(plan.stages)
              if k >= plan.likely and label in shot_start_confidences]
    stages = list(plan.stages[:plan.likely])
    if others:
        _, k, _ = max(others, key=lambda other: (other[0], -other[1]))  # a tie: the earlier stage
        stages.append(plan.stages[k])
    return SearchPlan(stages, plan.likely, new_shot=True)
