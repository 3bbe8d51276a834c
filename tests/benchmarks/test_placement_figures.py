"""The figures of ``bench placements --random N``'s report: outcomes and twins counted per route, each miss's cause,
the reachable frames, the frames whose visible paint fixes the camera, and the frames counted by look."""

from __future__ import annotations

from broadtrack_graph.benchmarks import placement_figures
from broadtrack_graph.benchmarks.random_cameras import STANDS


def test_route_figures_count_the_twins_with_the_found_and_apart_from_the_wrong():
    route_figures = placement_figures.route_figures

    def row(outcome_name, twin=None):
        result = {"outcome": outcome_name, "seconds": 0.1}
        if twin is not None:
            result["twin"] = twin
        return {"routes": {"court": result}, "truth_written": True}

    rows = [row("found"), row("wrong", True), row("wrong", False), row("none"), row("near", True)]
    figures = route_figures(rows, "court")
    assert (figures["found"], figures["wrong"], figures["wrong_twin"], figures["near"]) == (1, 2, 1, 1)
    assert (figures["found_or_twin"], figures["wrong_not_twin"]) == (2, 1)  # a near twin is neither
    shares = (figures["found_or_twin_pct"], figures["wrong_not_twin_pct"], figures["wrong_twin_pct"])
    assert shares == (40.0, 20.0, 20.0)
    assert route_figures([], "court")["found_or_twin_pct"] is None


def test_the_plain_renderers_frames_are_counted_by_whether_their_look_smears_them():
    def row(look, motion_blur_px=None):
        out = {"look": look, "determinable": True, "class": STANDS[0], "low": False, "render_s": 0.1,
               "detect_s": 0.1, "routes": {"court": {"outcome": "found", "seconds": 0.1}}, "truth_written": True}
        if motion_blur_px is not None:
            out["plain_look"] = {"motion_blur_px": motion_blur_px}
        return out

    rows = [row("clean"), row("blur"), row("clean"), row("plain", 0.0), row("plain", 12.5), row("plain", 0.0)]
    assert [placement_figures.look_group(r) for r in rows] == ["clean", "blur", "clean", "plain, sharp",
                                                              "plain, motion blur", "plain, sharp"]
    by_look = placement_figures.summarise(rows, ["court"])["by_route"]["court"]["by_look"]
    assert {look: figures["frames"] for look, figures in by_look.items()} == {
        "blur": 1, "clean": 2, "plain, motion blur": 1, "plain, sharp": 2}


def test_each_miss_has_one_cause_and_the_reachable_frames_are_counted_apart():
    def row(outcome_name, visible=True, detected=True, written=True, twin=None):
        result = {"outcome": outcome_name, "seconds": 0.1, **({} if twin is None else {"twin": twin})}
        return {"routes": {"court": result}, "markings_visible": visible, "markings_detected": detected,
                "truth_written": written}

    rows = [row("found"), row("wrong", twin=True), row("none", visible=False, detected=False, written=False),
            row("none", detected=False), row("none", detected=False, written=False), row("wrong", written=False),
            row("none"), row("near"), row("wrong", twin=False), row("found", detected=False)]
    rows[6]["routes"]["court"]["right_under_bar"] = True  # the truth (or its twin) returned, under the bar
    figures = placement_figures.route_figures(rows, "court")
    assert figures["misses_by_cause"] == {"paint_not_shown": 1, "not_detected": 2, "truth_under_bar": 1,
                                          "right_under_bar": 1, "route": 2}
    assert sum(figures["misses_by_cause"].values()) == len(rows) - figures["found_or_twin"]
    # reachable: detected and written (found, twin, none, near, wrong not a twin): 2 of those 5 found or twin
    assert (figures["reachable"], figures["found_or_twin_of_reachable_pct"]) == (5, 40.0)
    assert placement_figures.route_figures([], "court")["found_or_twin_of_reachable_pct"] is None
    # of the 9 frames whose visible paint fixes the camera: 3 found or twin, 2 wrong and not twins
    assert figures["markings_visible"] == 9
    assert (figures["found_or_twin_of_visible_pct"], figures["wrong_not_twin_of_visible_pct"]) == (33.3, 22.2)
    assert placement_figures.route_figures([], "court")["wrong_not_twin_of_visible_pct"] is None


def test_a_true_camera_under_the_routes_own_bar_is_not_reachable_by_it():
    # Written at the tracker's bar, but under the court model's (its camera is taken higher without a grid of lines)
    row = {"routes": {"court": {"outcome": "none", "seconds": 0.1, "truth_written": False}},
           "markings_visible": True, "markings_detected": True, "truth_written": True}
    figures = placement_figures.route_figures([row], "court")
    assert figures["misses_by_cause"]["truth_under_bar"] == 1 and figures["reachable"] == 0
    assert figures["truth_written"] == 0
    del row["routes"]["court"]["truth_written"]  # a report written before the routes had their own bar
    assert placement_figures.route_figures([row], "court")["misses_by_cause"]["route"] == 1
