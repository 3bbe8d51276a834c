"""The global search's stages (broadtrack_graph.track.search_stages): a new shot's plan and a mid-shot one."""

from __future__ import annotations

from broadtrack_graph.track.search_stages import DEFAULT_STAGE, KNOWN_CAMERAS, search_plan

KNOWN = {"main": (0.0, 55.0, -12.0), "high-behind-1": (-75.0, 0.0, -24.0)}


def _labels(plan):
    return [label for label, _ in plan.stages]


def test_a_new_shot_is_searched_at_the_known_cameras_then_the_default_positions():
    plan = search_plan(KNOWN, None, None, with_map=True)
    assert plan.new_shot and _labels(plan) == [KNOWN_CAMERAS, DEFAULT_STAGE[0]]
    assert plan.stages[0][1] == list(KNOWN.values()) and plan.stages[1] == DEFAULT_STAGE
    assert search_plan({}, None, None, with_map=True).stages == [DEFAULT_STAGE]
    # Labelled detections (no map): the same stages, not read on until a camera is certain.
    unlabelled = search_plan(KNOWN, None, None, with_map=False)
    assert not unlabelled.new_shot and _labels(unlabelled) == [KNOWN_CAMERAS, DEFAULT_STAGE[0]]


def test_a_mid_shot_loss_is_searched_at_its_own_camera_s_position():
    mid_shot = search_plan(KNOWN, "main", None, with_map=True)
    assert not mid_shot.new_shot and _labels(mid_shot) == ["camera main", DEFAULT_STAGE[0]]
    assert mid_shot.stages[0][1] == [KNOWN["main"]]
    # A trusted chain's camera dipping under the threshold stands where its confident frames put it.
    assert _labels(search_plan(KNOWN, "main", None, with_map=True, held_trusted=True)) == ["camera main"]
    # Another kind's camera: its own position alone, with a map or without.
    for with_map in (True, False):
        assert _labels(search_plan(KNOWN, "high-behind-1", None, with_map)) == ["camera high-behind-1"]


def test_given_positions_are_searched_alone():
    given = [(1.0, 60.0, -10.0)]
    for camera_id in (None, "main"):
        assert search_plan(KNOWN, camera_id, given, with_map=True).stages == [("the given positions", given)]


def test_where_the_court_model_looks_a_new_shot_is_searched_for_a_returning_camera_and_a_known_one_at_its_position():
    new_shot = search_plan(KNOWN, None, None, with_map=True, court_looks=True)
    assert new_shot.stages == [(KNOWN_CAMERAS, list(KNOWN.values()))] and new_shot.returning_only
    assert search_plan({}, None, None, with_map=True, court_looks=True).stages == []
    assert not search_plan(KNOWN, None, None, with_map=True).returning_only
    assert _labels(search_plan(KNOWN, "main", None, with_map=True, court_looks=True)) == ["camera main"]
    # Labelled detections have no map for it: the default positions are searched.
    assert _labels(search_plan(KNOWN, None, None, with_map=False, court_looks=True)) == [KNOWN_CAMERAS,
                                                                                         DEFAULT_STAGE[0]]
