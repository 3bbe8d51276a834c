"""The global search route (track/search_route.py): which stage's camera it keeps, when it stops, what it pays."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.reinit.scoring import LabelledScore, ReinitResult
from broadtrack_graph.track.camera_ids import CameraRegistry
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.search_route import SearchRoute
from broadtrack_graph.track.search_stages import SearchPlan
from broadtrack_graph.track.stage_runner import StageRunner

CONFIG = TrackingConfig(search_workers=0)


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
    route = SearchRoute(CONFIG, StageRunner(search, workers=0), CameraRegistry(), counts)
    plan = lambda likely, new_shot=False: SearchPlan([(k, [k]) for k in confidences_by_stage], likely, new_shot)  # noqa: E731
    score = lambda camera: float(camera.position_m[0] / 100.0)  # noqa: E731
    return route, plan, score, asked, counts


def test_a_likely_stage_s_better_camera_wins_a_later_one_only_by_the_margin():
    margin = CONFIG.reinit_switch_margin
    route, plan, score, asked, counts = _route({"known": 0.3, "default": 0.45, "other": 0.45 + 0.5 * margin,
                                                "far": None})
    found, confidence, label = route.run(plan(2), 0, False, True, 0.6, (None,) * 5, score)
    assert confidence == 0.45 and "default" in label  # the likely stages' better one; "other" is not better by the margin
    assert asked == ["known", "default", "other", "far"] and counts == {"global": 1, "stages": 4}
    route, plan, score, asked, _ = _route({"known": 0.3, "default": 0.45, "other": 0.45 + 1.5 * margin, "far": 0.9})
    found, confidence, label = route.run(plan(2), 0, False, True, 0.6, (None,) * 5, score)
    assert label.startswith("global search, other") and asked == ["known", "default", "other"]  # confident: it stops


def test_a_new_shot_reads_on_until_a_camera_is_certain_and_keeps_its_first_search_s_confidences():
    # 0.75 ends a search mid-shot (over the threshold), not a new shot's (under certain_confidence).
    stages = {"known": 0.7, "default": 0.75, "other": None, "far": 0.75 + 1.5 * CONFIG.reinit_switch_margin}
    route, plan, score, asked, _ = _route(stages)
    found, confidence, _ = route.run(plan(2, new_shot=True), 0, False, True, 0.6, (None,) * 5, score)
    assert asked == list(stages) and confidence == stages["far"]
    mid_shot, plan, score, asked, _ = _route(stages)
    mid_shot.run(plan(2), 0, False, True, 0.6, (None,) * 5, score)
    assert asked == ["known"]  # mid-shot the threshold ends it
    assert route.shot_start_confidences == {"known": 0.7, "default": 0.75, "far": stages["far"]}
    route.new_stretch()
    assert route.shot_start_confidences is None


def test_a_search_that_finds_nothing_trusted_makes_the_next_one_wait():
    route, plan, score, _, _ = _route({"known": 0.2, "default": None})
    assert route.budget.allows(0)
    route.run(plan(2), 0, False, True, 0.6, (None,) * 5, score)
    assert not route.budget.allows(1) and route.budget.next_frame(1) > 1
    found_route, plan, score, _, _ = _route({"known": 0.8, "default": None})
    found_route.run(plan(2), 0, False, True, 0.6, (None,) * 5, score)
    assert found_route.budget.next_frame(1) < route.budget.next_frame(1)
    unmapped, plan, score, _, _ = _route({"known": 0.2, "default": None})
    unmapped.run(plan(2), 0, False, False, 0.6, (None,) * 5, score)  # no marking map: not budgeted
    assert unmapped.budget.allows(1)
    assert np.isfinite(route.budget.next_frame(1))
