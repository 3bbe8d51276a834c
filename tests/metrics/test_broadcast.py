"""Scores of a tracked broadcast against its truth, on hand-made shots and ids with exact figures."""

from __future__ import annotations

import pytest

from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.metrics.broadcast import (
    camera_id_scores,
    cut_scores,
    frame_kinds,
    frames_by_kind,
    kind_group,
    kind_scores,
    tripod_scores,
)
from broadtrack_graph.types.shot import Shot

TRUE = [Shot(0, 10, "main", "main"), Shot(10, 14, "close-up", None, "hard"), Shot(14, 20, "main", "main", "hard"),
        Shot(20, 26, "other-camera", "high", "hard"), Shot(26, 30, "crowd", None, "hard")]


def test_cuts_found_within_two_frames():
    predicted = [Shot(0, 12, "main", "main"), Shot(12, 14, "close-up", None), Shot(14, 23, "main", "main"),
                 Shot(23, 30, "crowd", None)]
    scores = cut_scores(TRUE, predicted)
    # true cuts 10, 14, 20, 26; predicted 12 (finds 10 and 14), 14 (14), 23 (none) -> 10 and 14 found
    assert scores == {"true_cuts": 4, "predicted_cuts": 3, "found": 2, "recall": 0.5, "false_cuts": 1,
                      "missed": [20, 26]}
    assert cut_scores(TRUE, [])["found"] == 0 and cut_scores(TRUE[:1], [])["recall"] is None


def test_shot_kinds_by_group_and_exactly():
    predicted = frame_kinds([Shot(0, 10, "main", "main"), Shot(10, 13, "close-up", None),
                             Shot(13, 26, "main", "main"), Shot(26, 28, "close-up", None)], 30)
    assert predicted[28:] == [None, None] and predicted[12:14] == ["close-up", "main"]
    scores = kind_scores(TRUE, predicted)
    # main: main (exact); close-up: 3 close-up + 1 main -> close-up (exact); main: main; other-camera: main (group
    # only); crowd: 2 close-up, 2 unknown -> close-up (group only)
    assert [s["predicted_kind"] for s in scores["per_shot"]] == ["main", "close-up", "main", "main", "close-up"]
    assert scores["exact_agreement"] == 0.6 and scores["group_agreement"] == 1.0 and scores["shots"] == 5
    assert kind_group("other-camera") == "pitch" and kind_group("crowd") == "no-pitch" and kind_group(None) is None


def test_camera_ids_mapped_by_majority():
    true = ["A"] * 4 + [None] * 2 + ["B"] * 4 + ["A"] * 2
    predicted = ["m", "m", "m", None, None, "m", "x", "x", "m", None, "m", "m"]
    scores = camera_id_scores(true, predicted)
    # A: m x5 -> m; B: x x2, m x1 -> x; m is owned by A (5 frames vs 1), x by B
    assert scores["mapping"] == {"A": "m", "B": "x"} and scores["one_to_one"] is True
    assert scores["pitch_frames"] == 10 and scores["frames_with_id"] == 8
    assert scores["per_camera"] == {"A": {"frames": 6, "with_id": 5, "right": 5},
                                    "B": {"frames": 4, "with_id": 3, "right": 2}}
    assert scores["right_camera_share"] == 0.7


def test_camera_ids_of_a_tracker_that_knows_one_camera():
    scores = camera_id_scores(["A", "A", "B", "B", "B"], ["main", "main", "main", None, None])
    assert scores["mapping"] == {"A": "main", "B": "main"} and scores["one_to_one"] is False
    assert scores["right_camera_share"] == 0.4  # "main" is owned by A (2 frames vs 1)
    assert camera_id_scores(["A", "B"], [None, None])["mapping"] == {"A": None, "B": None}
    with pytest.raises(ValueError, match="as many"):
        camera_id_scores(["A"], [])


def test_frames_grouped_by_true_kind():
    groups = frames_by_kind(TRUE)
    assert groups == {"main": list(range(0, 10)) + list(range(14, 20)), "other-camera": list(range(20, 26))}
    assert frames_by_kind(TRUE, ("crowd",)) == {"crowd": [26, 27, 28, 29]}


def test_tripod_errors_through_the_mapping():
    truth = {"A": Tripod((0.0, 55.0, -12.0), 0.22), "B": Tripod((-75.0, 0.0, -24.0), 0.25)}
    run = {"m": Tripod((3.0, 59.0, -12.5), 0.2)}
    scores = tripod_scores(truth, run, {"A": "m", "B": None})
    assert scores["B"] is None
    assert scores["A"]["predicted_id"] == "m" and scores["A"]["T_error_xy_m"] == 5.0
    assert scores["A"]["T_error_m"] == pytest.approx(5.0249, abs=1e-4) and scores["A"]["delta_error_m"] == -0.02
