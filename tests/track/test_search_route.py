"""The global search route (track/search_route.py): which stage's camera it keeps, when it stops, what it pays."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.reinit.scoring import LabelledScore, ReinitResult
from broadtrack_graph.track.camera_ids import CameraRegistry
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.search_route import SearchRoute
from broadtrack_graph.track.search_stages import SearchPlan

CONFIG = TrackingConfig()


def _camera(x_m: float) -> Camera:
    return Camera.from_degrees(1500.0, 0.0, 0.0, 75.0, 0.0, (x_m, 60.0, -15.0), 1280, 720)


def _route(confidences_by_stage: dict[str, float | None]):
    """A route whose search gives, at each stage, a camera standing at x = that stage's confidence * 100 m (None: no
    camera), scored by that confidence."""
    asked = []

    def search(observations, detections, pitch, positions, curves, sampling):
        label = positions[0]
        asked.append(label)
        confidence = confidences_by_stage[label]
        if confidence is None:
            return ReinitResult(None, None, "", f"nothing at {label}")
        return ReinitResult(_camera(100.0 * confidence), LabelledScore(confidence, 0, 0, 0, 0.0, 0.0), label)

    counts = {"global": 0, "stages": 0}
    route = SearchRoute(CONFIG, search, CameraRegistry(), counts)
    plan = lambda new_shot=False: SearchPlan([(k, [k]) for k in confidences_by_stage], new_shot)  # noqa: E731
    score = lambda camera: float(camera.position_m[0] / 100.0)  # noqa: E731
    return route, plan, score, asked, counts


def test_the_best_stage_s_camera_wins():
    route, plan, score, asked, counts = _route({"known": 0.3, "default": 0.45, "far": None})
    found, confidence, label = route.run(plan(), 0, False, True, 0.6, (None,) * 5, score)
    assert confidence == 0.45 and label.startswith("global search, default")
    assert asked == ["known", "default", "far"] and counts == {"global": 1, "stages": 3}
    route, plan, score, asked, _ = _route({"known": None, "default": None})
    assert route.run(plan(), 0, False, True, 0.6, (None,) * 5, score)[0] is None


def test_a_new_shot_reads_on_until_a_camera_is_certain_and_its_first_search_empties_the_budget():
    # 0.75 ends a search mid-shot (over the threshold), not a new shot's (under certain_confidence).
    stages = {"known": 0.7, "default": 0.75, "other": None, "far": 0.95}
    route, plan, score, asked, _ = _route(stages)
    found, confidence, _ = route.run(plan(new_shot=True), 0, False, True, 0.6, (None,) * 5, score)
    assert asked == list(stages) and confidence == stages["far"]
    certain, plan, score, asked, _ = _route({"known": 0.95, "default": 0.97})
    certain.run(plan(new_shot=True), 0, False, True, 0.6, (None,) * 5, score)
    assert asked == ["known"]  # certain: it stops
    mid_shot, plan, score, asked, _ = _route(stages)
    mid_shot.run(plan(), 0, False, True, 0.6, (None,) * 5, score)
    assert asked == ["known"]  # mid-shot the threshold ends it
    # The shot's first search on a map leaves the bucket empty; a later one (after some frames) goes into debt.
    first, plan, score, _, _ = _route({"known": 0.2, "default": None})
    first.run(plan(new_shot=True), 0, False, True, 0.6, (None,) * 5, score)
    assert first.shot_searched and first.budget.tokens == 0.0
    first.run(plan(new_shot=True), 50, False, True, 0.6, (None,) * 5, score)
    assert first.budget.tokens < 0.0
    first.new_stretch()
    assert not first.shot_searched and first.budget.allows(51)


def test_a_search_that_finds_nothing_trusted_makes_the_next_one_wait():
    route, plan, score, _, _ = _route({"known": 0.2, "default": None})
    assert route.budget.allows(0)
    route.run(plan(), 0, False, True, 0.6, (None,) * 5, score)
    assert not route.budget.allows(1) and route.budget.next_frame(1) > 1
    found_route, plan, score, _, _ = _route({"known": 0.8, "default": None})
    found_route.run(plan(), 0, False, True, 0.6, (None,) * 5, score)
    assert found_route.budget.next_frame(1) < route.budget.next_frame(1)
    unmapped, plan, score, _, _ = _route({"known": 0.2, "default": None})
    unmapped.run(plan(), 0, False, False, 0.6, (None,) * 5, score)  # no marking map: not budgeted
    assert unmapped.budget.allows(1)
    assert np.isfinite(route.budget.next_frame(1))
