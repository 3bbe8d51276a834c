"""The ``broadcast`` synthetic preset: the shot plan, the truth files and the rendered views (small clip)."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from broadtrack_graph.geometry.tripod import tripod_residual
from broadtrack_graph.io.annotations import read_annotations
from broadtrack_graph.io.broadcast_truth import read_broadcast_truth
from broadtrack_graph.io.cameras import read_camera_file
from broadtrack_graph.shots.views import classify_view
from broadtrack_graph.synth.broadcast import DEFAULT_PLAN, broadcast_plan, broadcast_scene
from broadtrack_graph.synth.presets import PRESETS
from broadtrack_graph.synth.writer import write_synthetic_clip

FRAMES, WIDTH, HEIGHT = 60, 320, 180


@pytest.fixture(scope="module")
def clip(tmp_path_factory):
    out = tmp_path_factory.mktemp("broadcast") / "clip"
    write_synthetic_clip(out, preset="broadcast", frame_count=FRAMES, width_px=WIDTH, height_px=HEIGHT, seed=0,
                         progress=False)
    return out


def test_full_length_plan_is_the_default_plan():
    shots = broadcast_plan(1500)
    assert [s.frames for s in shots] == [frames for _, frames in DEFAULT_PLAN]
    assert [s.kind for s in shots] == ["main", "close-up", "main", "other-camera", "main", "other-camera", "crowd",
                                      "close-up", "main", "other-camera", "main"]
    assert [s.camera_id for s in shots][3::6] == ["high-behind", "high-behind"]  # the high camera returns
    assert all(60 <= s.frames <= 300 for s in shots)


@pytest.mark.parametrize("frames, least", [(60, 5), (55, 5), (54, 2), (22, 2), (3000, 120)])
def test_plan_scales_with_the_length_and_keeps_every_shot(frames, least):
    shots = broadcast_plan(frames)
    assert shots[0].start == 0 and shots[-1].end == frames
    assert all(a.end == b.start for a, b in zip(shots, shots[1:]))
    assert min(s.frames for s in shots) >= least


def test_plan_refuses_too_few_frames():
    with pytest.raises(ValueError, match="at least 22 frames"):
        broadcast_plan(21)


def test_scene_is_deterministic_and_each_camera_keeps_its_tripod():
    a = broadcast_scene(60, WIDTH, HEIGHT, seed=3)
    b = broadcast_scene(60, WIDTH, HEIGHT, seed=3)
    np.testing.assert_array_equal([c.to_vector() for c in a.cameras], [c.to_vector() for c in b.cameras])
    assert a.tripods["low-16m"].T_w == PRESETS["low-16m"].tripod_T_w
    for i, cid in enumerate(a.camera_ids):
        if cid is not None:  # every pitch frame, before and after the cuts, on its camera's tripod
            camera = a.cameras[i]
            assert abs(tripod_residual(camera.position_m, camera.R_cw, a.tripods[cid])) < 1e-9


def test_truth_files_describe_the_plan(clip):
    truth = read_broadcast_truth(clip)
    plan = broadcast_plan(FRAMES)
    assert [(s.start, s.end, s.kind, s.camera_id) for s in truth.shots] == [
        (s.start, s.end, s.kind, s.camera_id) for s in plan]
    assert [s.boundary for s in truth.shots] == ["start"] + ["hard"] * (len(plan) - 1)
    assert sorted(truth.tripods) == ["high-behind", "low-16m", "main"]
    assert len(truth.camera_ids) == FRAMES
    for shot in truth.shots:
        assert set(truth.camera_ids[shot.start:shot.end]) == {shot.camera_id}


def test_ground_truth_cameras_and_annotations_only_on_pitch_frames(clip):
    truth = read_broadcast_truth(clip)
    pitch_ids = {f"{i + 1:06d}" for i, c in enumerate(truth.camera_ids) if c is not None}
    assert {p.stem.removeprefix("camera_") for p in (clip / "cameras").glob("camera_*.json")} == pitch_ids
    assert set(read_annotations(clip).frames) <= pitch_ids
    assert len(list((clip / "img1").glob("*.jpg"))) == FRAMES


def test_a_returning_camera_keeps_its_tripod(clip):
    truth = read_broadcast_truth(clip)
    high = [s for s in truth.shots if s.camera_id == "high-behind"]
    assert len(high) == 2 and high[1].start > high[0].end
    for shot in high:
        for i in (shot.start, shot.end - 1):
            camera = read_camera_file(clip / "cameras" / f"camera_{i + 1:06d}.json")
            assert abs(tripod_residual(camera.position_m, camera.R_cw, truth.tripods["high-behind"])) < 1e-6


def test_close_ups_and_crowd_shots_are_classified_as_such(clip):
    truth = read_broadcast_truth(clip)
    no_pitch = [s for s in truth.shots if s.camera_id is None]
    assert sorted({s.kind for s in no_pitch}) == ["close-up", "crowd"]
    for shot in no_pitch:
        for i in range(shot.start, shot.end):
            view = classify_view(cv2.imread(str(clip / "img1" / f"{i + 1:06d}.jpg")))
            assert view.kind == shot.kind, (i, view.reason)


def test_synth_command_refuses_a_broadcast_too_short_or_along_given_cameras(tmp_path):
    from broadtrack_graph.cli import main

    assert main(["synth", "--preset", "broadcast", "--frames", "21", "--out", str(tmp_path / "a")]) == 2
    assert main(["synth", "--preset", "broadcast", "--frames", "30", "--cameras", str(tmp_path),
                 "--out", str(tmp_path / "b")]) == 2
    assert not (tmp_path / "a").exists() and not (tmp_path / "b").exists()
