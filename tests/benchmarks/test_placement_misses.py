"""The causes of a random placement's miss (broadtrack_graph.benchmarks.placement_misses)."""

from __future__ import annotations

from broadtrack_graph.benchmarks.placement_misses import MISS_CAUSES, miss_cause, truth_written


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
