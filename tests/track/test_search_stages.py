"""The global search's stages (broadtrack_graph.track.search_stages): a shot's first plan and its later ones."""

from __future__ import annotations

from broadtrack_graph.track.search_stages import (
    KNOWN_CAMERAS,
    SEARCH_STAGES,
    retry_plan,
    search_plan,
)

KNOWN = {"main": (0.0, 55.0, -12.0)}


def _labels(plan):
    return [label for label, _ in plan.stages]


def test_a_new_shot_is_planned_through_every_stage_and_a_mid_shot_loss_through_its_camera_s():
    plan = search_plan(KNOWN, None, None, with_map=True)
    assert plan.new_shot and plan.likely == 2
    assert _labels(plan) == [KNOWN_CAMERAS] + [s[0] for s in SEARCH_STAGES]
    mid_shot = search_plan(KNOWN, "main", None, with_map=True)
    assert not mid_shot.new_shot and _labels(mid_shot) == ["camera main", "default positions"]
    # A trusted chain's camera dipping under the threshold stands where its confident frames put it.
    held = search_plan(KNOWN, "main", None, with_map=True, held_trusted=True)
    assert not held.new_shot and held.likely == 1 and _labels(held) == ["camera main"]
    assert _labels(search_plan(KNOWN, None, None, with_map=False)) == [KNOWN_CAMERAS, "default positions"]


def test_a_shot_s_later_search_tries_the_likely_stages_and_the_one_that_came_nearest():
    full = search_plan(KNOWN, None, None, with_map=True)
    corner, far = "high-corner cameras", "main camera further back"
    # The likely stages' own confidences do not matter: they are searched anyway.
    plan = retry_plan(full, {KNOWN_CAMERAS: 0.45, "default positions": 0.4, far: 0.3, corner: 0.35})
    assert plan.new_shot and plan.likely == 2
    assert _labels(plan) == [KNOWN_CAMERAS, "default positions", corner]
    assert search_plan(KNOWN, None, None, True, {far: 0.3, corner: 0.35}) == plan
    # A tie goes to the earlier stage; no camera: the likely stages only.
    assert _labels(retry_plan(full, {corner: 0.3, far: 0.3}))[-1] == far
    assert _labels(retry_plan(full, {})) == [KNOWN_CAMERAS, "default positions"]
