"""The causes of a random placement's miss and a route's second look (broadtrack_graph.benchmarks.placement_misses)."""

from __future__ import annotations

import dataclasses

import numpy as np

from broadtrack_graph.benchmarks.placement_frames import draw_frame
from broadtrack_graph.benchmarks.placement_misses import (
    MISS_CAUSES,
    markings_detected,
    miss_cause,
    second_look_reach,
    truth_written,
)
from broadtrack_graph.detect.weightfree import WeightFreeDetector
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateSampling, fitting_curves


def _row(visible=True, detected=True, written=True, route_written=None, right=None):
    result = {"outcome": "none"}
    if route_written is not None:
        result["truth_written"] = route_written
    if right is not None:
        result["right_under_bar"] = right
    return {"routes": {"court": result}, "markings_visible": visible, "markings_detected": detected,
            "truth_written": written}


def test_the_first_cause_that_applies_is_the_one_given():
    assert miss_cause(_row(visible=False, detected=False, written=False), "court") == "paint_not_shown"
    assert miss_cause(_row(detected=False, written=False), "court") == "not_detected"
    assert miss_cause(_row(written=False), "court") == "truth_under_bar"
    assert miss_cause(_row(right=True), "court") == "right_under_bar"
    assert miss_cause(_row(right=False), "court") == "route"
    assert set(MISS_CAUSES) == {"paint_not_shown", "not_detected", "truth_under_bar", "right_under_bar", "route"}


def test_the_routes_own_bar_decides_over_the_rows():
    # written at the tracker's bar, not at the route's: under the bar for this route
    assert not truth_written(_row(written=True, route_written=False), "court")
    assert miss_cause(_row(written=True, route_written=False, right=True), "court") == "truth_under_bar"
    assert truth_written(_row(written=False, route_written=True), "court")
    # a row written before the routes had their own bar: the row's
    assert truth_written(_row(written=True), "court") and not truth_written(_row(written=False), "court")
    assert not truth_written(_row(written=False), "tracker")  # a route the row did not run: the row's


def _second(row: dict, detected: bool, written: bool) -> dict:
    row["routes"]["court"]["second_look"] = {"markings_detected": detected, "truth_written": written}
    return row


def test_the_routes_second_look_counts_as_detected_and_written():
    # Fixed on the faint look alone (a smeared frame): the route could reach it, its miss is its own.
    row = _second(_row(detected=False, written=False, route_written=False, right=False), True, True)
    assert markings_detected(row, "court") and truth_written(row, "court")
    assert miss_cause(row, "court") == "route"
    # Fixed there, but the truth under the bar on both looks.
    row = _second(_row(detected=False, written=False, route_written=False), True, False)
    assert miss_cause(row, "court") == "truth_under_bar"
    # Neither look fixes it.
    row = _second(_row(detected=False, written=False, route_written=False), False, False)
    assert miss_cause(row, "court") == "not_detected"
    # Another route's second look says nothing of this one's.
    assert not markings_detected(row, "tracker") and not truth_written(_row(written=False), "tracker")


def test_second_look_reach_reads_the_truth_on_the_looks_markings():
    """On a rendered frame's own detections the true camera's markings are fixed and it is confident; on a map
    with no marking neither. The bar is asked with what the truth explains."""
    frame = draw_frame(36, 3, 960, 540, ["clean"])
    truth = frame["drawn"].camera
    pitch = PitchTemplate()
    curves, sampling = fitting_curves(pitch), TemplateSampling(pitch)
    detector = WeightFreeDetector(pitch)
    detections = detector.name(detector.find_markings(frame["image"]))
    asked = []

    def bar_of(seen):
        asked.append(seen)
        return 0.6 if seen.line_grid else 0.7

    reach = second_look_reach(truth, detections, (960, 540), pitch, curves, sampling, bar_of)
    assert reach["markings_detected"] and reach["truth_written"] and reach["truth_confidence"] >= 0.7
    assert len(asked) == 1 and asked[0].determinable
    empty = dataclasses.replace(detections, marking_mask=np.zeros_like(detections.marking_mask),
                                marking_points_px=np.zeros((0, 2)))
    reach = second_look_reach(truth, empty, (960, 540), pitch, curves, sampling, bar_of)
    assert not reach["markings_detected"] and not reach["truth_written"]
