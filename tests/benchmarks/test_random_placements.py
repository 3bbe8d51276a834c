"""``bench placements --random N`` end to end on two frames, the court route's wiring, and the outcome rule."""

from __future__ import annotations

import json
import math
import sys

import numpy as np

from broadtrack_graph.benchmarks import placement_frames, random_placements
from broadtrack_graph.benchmarks.placement_frames import RANDOM_STREAM
from broadtrack_graph.benchmarks.random_cameras import STANDS, draw_random_camera
from broadtrack_graph.benchmarks.random_placements import outcome, twin_outcome
from broadtrack_graph.cli import main
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.court_fit import twin_camera
from broadtrack_graph.reinit.scoring import ReinitResult
from broadtrack_graph.track.config import TrackingConfig

# Frames 3 and 4 of seed 36 at 960x540: a main-stand camera the shipped field model finds (under a tenth of a
# second), and one whose markings do not determine a camera (each under a second of search).
SEED, FIRST, WIDTH, HEIGHT = 36, 3, 960, 540


def run_bench(tmp_path, *extra) -> dict:
    out = tmp_path / "report.json"
    code = main(["bench", "placements", "--random", "2", "--first", str(FIRST), "--seed", str(SEED),
                 "--width", str(WIDTH), "--height", str(HEIGHT), "--no-progress", "--json", str(out), *extra])
    assert code == 0
    return json.loads(out.read_text(encoding="utf-8"))


def test_two_frames_end_to_end_with_the_search(tmp_path, capsys):
    report = run_bench(tmp_path, "--routes", "search", "--reinit-model", "shipped")
    assert report["suite"] == "placements" and report["mode"] == "random" and report["frames"] == 2
    assert report["routes"] == ["search"] and report["frame_size"] == [WIDTH, HEIGHT]
    rows = report["frames_by_index"]
    assert [row["frame"] for row in rows] == [FIRST, FIRST + 1]
    for row in rows:
        assert {"camera", "look", "class", "determinable", "markings", "truth_confidence", "render_s",
                "markings_visible", "markings_detected"} <= set(row)
        assert row["class"] in STANDS and set(row["routes"]) == {"search"}
        assert {"outcome", "confidence", "error_px", "seconds", "reason"} <= set(row["routes"]["search"])
    assert report["determinable"] + report["not_determinable"] == 2
    figures = report["by_route"]["search"]
    assert set(figures) == {"determinable", "by_stand", "by_height", "by_look", "not_determinable"}
    assert set(figures["by_stand"]) == set(STANDS)
    looks = {row["look"] for row in rows if row["determinable"]}
    assert set(figures["by_look"]) == looks
    assert sum(group["frames"] for group in figures["by_look"].values()) == report["determinable"]
    assert figures["determinable"]["frames"] == report["determinable"]
    assert sum(figures["determinable"][o] for o in ("found", "near", "wrong", "none")) == report["determinable"]
    found = [row for row in rows if row["routes"]["search"]["outcome"] == "found"]
    assert found, [(row["class"], row["routes"]["search"]) for row in rows]
    assert all(row["determinable"] and row["routes"]["search"]["error_px"] < 1.0 for row in found)
    assert all(row["routes"]["search"]["confidence"] >= report["written_confidence"]["search"] for row in found)
    # The JSON on stdout is the report; the table goes to stderr.
    captured = capsys.readouterr()
    assert json.loads(captured.out)["frames_by_index"] == rows
    assert "search  all" in captured.err


def test_the_tracker_route_asks_the_policy_with_the_court_model(tmp_path):
    report = run_bench(tmp_path, "--routes", "tracker")
    assert report["routes"] == ["tracker"]
    first, second = (row["routes"]["tracker"] for row in report["frames_by_index"])
    # The main-stand camera: the court model places it at its first frame; the other frame's markings fix no
    # camera, and whatever a route proposes for it is dropped, quickly.
    assert first["outcome"] == "found" and first["error_px"] < 1.0 and first["reason"].startswith("court model")
    assert second["outcome"] == "none" and second["seconds"] < 1.0
    assert [row["view"]["kind"] for row in report["frames_by_index"]] == ["main", "main"]  # the shot step's reading
    assert report["other_view"]["determinable"] == 0


def test_a_frame_the_shot_step_reads_as_another_view_is_looked_at_by_the_court_model_alone(tmp_path, monkeypatch):
    close_up = {"kind": "close-up", "reason": "close-up: a stand-in", "other_view": True}
    monkeypatch.setattr(random_placements, "shot_step_view", lambda image, detector: close_up)
    report = run_bench(tmp_path, "--routes", "tracker", "search", "court")
    first = report["frames_by_index"][0]
    assert first["view"] == close_up and report["other_view"]["determinable"] == int(first["determinable"])
    search = first["routes"]["search"]
    assert search["outcome"] == "none" and search["seconds"] == 0.0 and search["reason"].startswith("other view")
    # the tracker's court model places it as the single-frame calibrator does (the same camera, at its bar)
    tracker, court = first["routes"]["tracker"], first["routes"]["court"]
    assert court["outcome"] == "found" and tracker["reason"].startswith("court model")
    assert (tracker["outcome"], tracker["error_px"]) == (court["outcome"], court["error_px"])


def test_the_court_route_gets_the_marking_map_and_its_camera_is_judged(tmp_path, monkeypatch):
    truths = [draw_random_camera(np.random.default_rng([SEED, i, RANDOM_STREAM, 0]), WIDTH, HEIGHT).camera
              for i in (FIRST, FIRST + 1)]
    calls = []

    def stand_in(marking_mask, marking_points_px, frame_size, pitch=None, curves=None, field_mask=None,
                 player_mask=None, motion_blur=None):
        calls.append((marking_mask.dtype, marking_points_px.shape[1], frame_size, isinstance(pitch, PitchTemplate),
                      player_mask.dtype, motion_blur is None or motion_blur.length_px > 0))
        return ReinitResult(truths[len(calls) - 1], None, "stand-in", reason="the true camera")

    monkeypatch.setattr(random_placements, "_court_route", lambda: (stand_in, None))
    report = run_bench(tmp_path, "--routes", "court")
    # the players' mask too, and the frame's motion blur when the detector found one
    assert calls == [(np.dtype(bool), 2, (WIDTH, HEIGHT), True, np.dtype(bool), True)] * 2
    for row in report["frames_by_index"]:
        court = row["routes"]["court"]
        assert court["error_px"] == 0.0 and court["confidence"] == row["truth_confidence"]
        truth = truths[report["frames_by_index"].index(row)]
        assert court["camera"]["position_m"] == [round(float(v), 2) for v in truth.position_m]
        assert court["camera"]["focal_px"] == round(float(truth.focal_px), 1)
        # the stand-in's camera explains no markings: taken at the court bar without a grid of lines
        assert court["outcome"] == ("found" if court["confidence"] >= TrackingConfig().court_accept_confidence
                                    else "none")
        assert court["truth_written"] >= (court["outcome"] == "found")  # the true camera's own bar is never higher
        assert court["right_under_bar"] == (court["outcome"] == "none")  # the truth itself, not written
        # what detection leaves a route: never more than the frame's markings determine
        assert isinstance(row["markings_detected"], bool) and (row["determinable"] or not row["markings_detected"])
    figures = report["by_route"]["court"]["determinable"]
    assert figures["markings_detected"] == sum(r["markings_detected"] for r in report["frames_by_index"]
                                               if r["determinable"])


def test_a_court_route_that_cannot_be_imported_is_skipped_with_a_note(tmp_path, monkeypatch, capsys):
    monkeypatch.setitem(sys.modules, "broadtrack_graph.reinit.court", None)  # importing it raises ImportError
    report = run_bench(tmp_path, "--routes", "court")
    assert report["routes"] == [] and set(report["skipped_routes"]) == {"court"}
    assert report["by_route"] == {} and all(row["routes"] == {} for row in report["frames_by_index"])
    assert "route court skipped" in capsys.readouterr().err


def test_outcomes():
    assert outcome(0.9, 0.5, 0.6, 3.0) == "found"
    assert outcome(0.9, 3.0, 0.6, 3.0) == "found"
    assert outcome(0.9, 5.0, 0.6, 3.0) == "near"
    assert outcome(0.9, 10.5, 0.6, 3.0) == "wrong"
    assert outcome(0.59, 0.5, 0.6, 3.0) == "none"
    assert outcome(None, None, 0.6, 3.0) == "none"


def test_a_camera_off_the_truth_but_near_its_twin_is_judged_by_the_twin():
    assert twin_outcome("wrong", 2.0, 3.0) == ("wrong", True)  # the twin: counted with the found
    assert twin_outcome("wrong", 6.3, 3.0) == ("near", True)  # as near as a camera 6.3 px off the truth itself
    assert twin_outcome("wrong", 10.5, 3.0) == ("wrong", False)
    assert twin_outcome("wrong", None, 3.0) == ("wrong", False)
    assert twin_outcome("near", 1.0, 3.0) == ("near", False)  # nearer the truth than a twin could make it


def test_the_twin_sees_every_marking_where_the_camera_sees_its_mirror_image():
    camera = draw_random_camera(np.random.default_rng(2), 640, 360).camera
    points = np.vstack(list(PitchTemplate().sample_uniform(2.0).values()))
    uv, front = camera.project(points)
    uv_twin, front_twin = twin_camera(camera).project(points * np.array([-1.0, -1.0, 1.0]))
    assert np.array_equal(front, front_twin) and front.any()
    assert np.allclose(uv[front], uv_twin[front], atol=1e-6)
    assert math.isclose(twin_camera(twin_camera(camera)).position_m[0], camera.position_m[0])


def test_visible_paint_is_where_the_markings_show_and_fixes_the_camera_only_when_they_do():
    import dataclasses

    from broadtrack_graph.geometry.determinable import determinability
    from broadtrack_graph.synth.field_samples import render_look
    from broadtrack_graph.synth.named_looks import named_look

    frame = placement_frames.draw_frame(SEED, FIRST, WIDTH, HEIGHT, ["clean"])
    truth = frame["drawn"].camera
    assert determinability(truth).determinable
    shown = placement_frames.visible_paint(frame)
    assert shown.shape == (540, 960) and 0 < shown.mean() < 0.2
    assert determinability(truth, explained_by=shown).determinable
    # The same frame painted 1 cm wide at the grass's own brightness: nothing shows, nothing is determined.
    faint = dataclasses.replace(frame["look"], line_half_width_m=0.005, line_bgr=(90.0, 140.0, 90.0))
    frame = {**frame, "look": faint, "image": render_look(truth, frame["players"], faint, named_look("clean")).image}
    assert not determinability(truth, explained_by=placement_frames.visible_paint(frame)).determinable


def test_the_plain_renderer_draws_the_same_cameras_and_its_paint_shows(tmp_path, monkeypatch):
    truths = []

    def stand_in(marking_mask, marking_points_px, frame_size, pitch=None, curves=None, field_mask=None,
                 player_mask=None, motion_blur=None):
        return ReinitResult(None, None, "stand-in", reason="no camera")

    monkeypatch.setattr(random_placements, "_court_route", lambda: (stand_in, None))
    for renderer in ("synth", "plain"):
        report = run_bench(tmp_path, "--routes", "court", "--renderer", renderer)
        assert report["renderer"] == renderer
        truths.append([(row["camera"], row["determinable"]) for row in report["frames_by_index"]])
    assert truths[0] == truths[1]
    assert report["looks"] == ["plain"] and {row["look"] for row in report["frames_by_index"]} == {"plain"}
    assert all({"motion_blur_px", "jpeg_quality", "noise_sigma"} <= set(row["plain_look"])
               for row in report["frames_by_index"])
    from broadtrack_graph.geometry.determinable import determinability

    frame = placement_frames.draw_frame(SEED, FIRST, WIDTH, HEIGHT, ["clean"], "plain")
    shown = placement_frames.visible_paint(frame)
    assert 0 < shown.mean() < 0.2 and determinability(frame["drawn"].camera, explained_by=shown).determinable


def test_the_plain_renderer_is_asked_of_random_frames_only(capsys):
    assert main(["bench", "placements", "--renderer", "plain", "--distances", "55", "--elevations", "15"]) != 0
    assert "--renderer plain renders the frames of --random N only" in capsys.readouterr().err


def test_the_court_route_looks_again_on_the_faint_look_when_its_camera_is_under_its_bar(monkeypatch):
    """As the tracker at a new shot: the court model's camera on the markings as found, and when under its bar (0.7
    without a grid of lines) the one on their faint look, kept only when over its own bar."""
    from types import SimpleNamespace

    from broadtrack_graph.reinit import frame

    found, looked = (SimpleNamespace(marking_mask=np.ones((9, 16), bool), marking_points_px=np.zeros((5, 2)),
                                     field_mask=None, player_mask=None, motion_blur=None) for _ in range(2))
    cameras = {id(found): "on the markings as found", id(looked): "on the faint look"}

    def court(marking_mask, marking_points_px, frame_size, **kwargs):
        on = found if marking_mask is found.marking_mask else looked
        return ReinitResult(cameras[id(on)], None, "stand-in")

    def second(first_confidence, again_confidence, offered=True):
        scores = {id(found): first_confidence, id(looked): again_confidence}
        monkeypatch.setattr(frame, "frame_confidence",
                            lambda camera, observations, on, curves, sampling: scores[id(on)])
        asked = []
        look = (lambda: asked.append(1) or looked) if offered else None
        result, confidence, bar = random_placements._court_with_second_look(
            court, found, look, (WIDTH, HEIGHT), None, None, None, TrackingConfig())
        return result.camera, confidence, bar, len(asked)

    assert second(0.5, 0.8) == ("on the faint look", 0.8, 0.7, 1)
    assert second(0.5, 0.65) == ("on the markings as found", 0.5, 0.7, 1)  # under its bar there too
    assert second(0.75, 0.9) == ("on the markings as found", 0.75, 0.7, 0)  # taken at once: no second look
    assert second(0.5, 0.8, offered=False) == ("on the markings as found", 0.5, 0.7, 0)


def test_the_court_routes_second_look_is_kept_in_its_row_and_read_by_the_causes(tmp_path):
    """Plain seed 3's frame 106: the markings as found do not fix its camera, their faint look does (and the truth is
    confident on it), so the court model's miss there is the route's own, not the detector's."""
    out = tmp_path / "report.json"
    assert main(["bench", "placements", "--random", "1", "--first", "106", "--seed", "3", "--renderer", "plain",
                 "--routes", "court", "--no-progress", "--json", str(out)]) == 0
    report = json.loads(out.read_text(encoding="utf-8"))
    row = report["frames_by_index"][0]
    second = row["routes"]["court"].get("second_look")
    assert row["determinable"] and not row["markings_detected"], "the premise: the first look does not fix it"
    assert second is not None, "the premise: the court model looked again on the faint look"
    assert second["markings_detected"] and second["truth_written"] and second["truth_confidence"] >= 0.7
    figures = report["by_route"]["court"]["determinable"]
    assert figures["markings_detected"] == 1 and figures["reachable"] == 1
    court = row["routes"]["court"]
    if not (court["outcome"] == "found" or (court["outcome"] == "wrong" and court.get("twin"))):  # missed
        assert figures["misses_by_cause"]["route"] == 1 and figures["misses_by_cause"]["not_detected"] == 0
