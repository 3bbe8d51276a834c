"""End-to-end tracking on a small rendered HD clip: modes, outputs written as it goes, bad input."""

import json
import shutil

import numpy as np
import pytest

from broadtrack_graph.actions.track import track_input
from broadtrack_graph.detect.flow import on_pitch
from broadtrack_graph.errors import InputError
from broadtrack_graph.io.annotations import read_annotations
from broadtrack_graph.io.detections import annotations_to_observations
from broadtrack_graph.io.detections_writer import DetectionsWriter
from broadtrack_graph.io.frames import open_frames
from broadtrack_graph.io.run_folder import read_track
from broadtrack_graph.io.tripod_file import read_tripod
from broadtrack_graph.metrics.soccernet import evaluate_cameras
from broadtrack_graph.synth.writer import write_synthetic_clip
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.inputs import frames_from_source
from broadtrack_graph.track.passes import run_frames
from broadtrack_graph.track.run_context import RunContext

FRAMES = 24


@pytest.fixture(scope="module")
def clip(tmp_path_factory):
    out = tmp_path_factory.mktemp("clip") / "main"
    write_synthetic_clip(out, preset="main", frame_count=FRAMES, width_px=1920, height_px=1080, seed=3,
                         write_masks=False, progress=False)
    return out


def jac5(clip_dir, run_dir):
    annotations = read_annotations(clip_dir / "Labels-GameState.json")
    cameras = read_track(run_dir).cameras
    report = evaluate_cameras(annotations, cameras, 1920, 1080, taus=(5,))
    return report


def test_online_tracking_recovers_the_clip(clip, tmp_path):
    result = track_input(clip, tmp_path / "online", TrackingConfig(mode="online"), progress=False)
    report = jac5(clip, tmp_path / "online")
    assert report["completeness"] == 1.0
    assert report["accuracy"] >= 0.9
    assert report["mre_px"] < 2.5
    lines = (tmp_path / "online" / "track.jsonl").read_text().splitlines()
    assert len(lines) == FRAMES
    first = json.loads(lines[0])
    assert first["status"] == "reinitialised" and first["reinitialised"]
    assert all(json.loads(line)["status"] in ("tracked", "reinitialised") for line in lines)
    assert result.summary["complete"] and result.summary["frames_with_camera"] == FRAMES
    # Uncertainties are reported in their units.
    record = json.loads(lines[-1])
    assert 0 < record["pan_std_deg"] < 1 and 0 < record["focal_std_px"] < 200


def test_markings_found_ahead_in_the_decoding_thread_change_no_camera(clip, tmp_path, monkeypatch):
    from broadtrack_graph.io.prefetch import PREFETCH_ENV

    ahead = track_input(clip, tmp_path / "ahead", TrackingConfig(mode="online"), progress=False)
    monkeypatch.setenv(PREFETCH_ENV, "0")  # one thread: the same steps, in the caller's thread
    inline = track_input(clip, tmp_path / "inline", TrackingConfig(mode="online"), progress=False)
    assert ahead.summary["timings_s"]["markings_ahead_s"] > 0
    assert inline.summary["timings_s"]["markings_ahead_s"] > 0  # found by the same step, in the one thread
    files = sorted((tmp_path / "ahead" / "cameras").glob("*.json"))
    assert len(files) == FRAMES
    assert all(f.read_bytes() == (tmp_path / "inline" / "cameras" / f.name).read_bytes() for f in files)


def test_flow_tracked_ahead_in_the_decoding_thread_changes_no_camera(clip, tmp_path, monkeypatch):
    from broadtrack_graph.track import ahead, observe

    used = []
    monkeypatch.setattr(observe, "on_pitch", lambda *args: used.append(1) or on_pitch(*args))
    monkeypatch.setattr(ahead, "FLOW_AHEAD_MIN_LEAD", -FRAMES)  # always ahead
    track_input(clip, tmp_path / "ahead", TrackingConfig(mode="online"), progress=False)
    ahead_uses = len(used)
    assert ahead_uses >= FRAMES - 2  # every frame with a previous camera but the first
    monkeypatch.setattr(ahead, "FLOW_AHEAD_MIN_LEAD", 10 * FRAMES)  # never: the loop tracks it
    track_input(clip, tmp_path / "loop", TrackingConfig(mode="online"), progress=False)
    assert len(used) == ahead_uses
    files = sorted((tmp_path / "ahead" / "cameras").glob("*.json"))
    assert len(files) == FRAMES
    assert all(f.read_bytes() == (tmp_path / "loop" / "cameras" / f.name).read_bytes() for f in files)


def test_frames_prepared_in_a_process_of_their_own_change_no_camera(clip, tmp_path, monkeypatch):
    from broadtrack_graph.io.prefetch import PREFETCH_ENV
    from broadtrack_graph.track import ahead, passes

    monkeypatch.setattr(ahead, "PROCESS_MIN_FRAMES", 1)  # the clip is short: a process all the same
    fed = []
    monkeypatch.setattr(passes, "FramesInProcess", lambda *args: fed.append(1) or ahead.FramesInProcess(*args))
    in_process = track_input(clip, tmp_path / "process", TrackingConfig(mode="online"), progress=False)
    monkeypatch.setenv(PREFETCH_ENV, "thread")
    track_input(clip, tmp_path / "thread", TrackingConfig(mode="online"), progress=False)
    assert fed == [1]  # the first run only
    assert in_process.summary["timings_s"]["markings_ahead_s"] > 0  # found ahead, in the other process
    files = sorted((tmp_path / "process" / "cameras").glob("*.json"))
    assert len(files) == FRAMES
    assert all(f.read_bytes() == (tmp_path / "thread" / "cameras" / f.name).read_bytes() for f in files)
    assert (tmp_path / "process" / "shots.json").read_bytes() == (tmp_path / "thread" / "shots.json").read_bytes()


def test_fixed_lag_outputs_every_frame_in_order(clip, tmp_path):
    track_input(clip, tmp_path / "lag", TrackingConfig(mode="fixed-lag", lag_frames=5), progress=False)
    frames = [json.loads(line)["frame"] for line in (tmp_path / "lag" / "track.jsonl").read_text().splitlines()]
    assert frames == list(range(FRAMES))
    report = jac5(clip, tmp_path / "lag")
    assert report["completeness"] == 1.0 and report["accuracy"] >= 0.9


def test_batch_two_pass_writes_tripod(clip, tmp_path):
    result = track_input(clip, tmp_path / "batch", TrackingConfig(mode="batch"), progress=False)
    assert (tmp_path / "batch" / "pass1" / "track.jsonl").is_file()
    report = jac5(clip, tmp_path / "batch")
    assert report["completeness"] == 1.0 and report["accuracy"] >= 0.9
    tripod = read_tripod(tmp_path / "batch" / "tripod.json")
    truth = json.loads((clip / "tripod.json").read_text())
    assert result.tripod is not None
    # The summary says where the tripod came from, as tripod.json does.
    assert result.summary["tripod_fit"] == json.loads((tmp_path / "batch" / "tripod.json").read_text())["fit"]
    # Horizontal position of T is well determined even on a short clip.
    assert np.hypot(*(np.array(tripod.T_w[:2]) - truth["T_w"][:2])) < 2.0


def test_interrupted_run_keeps_every_frame_written(clip, tmp_path):
    source = open_frames(clip)

    def interrupted():
        for frame in frames_from_source(source):
            if frame.frame_index == 10:
                raise KeyboardInterrupt
            yield frame

    with pytest.raises(KeyboardInterrupt):
        run_frames(interrupted(), 1920, 1080, tmp_path / "cut",
                   RunContext(TrackingConfig(), _detector(), progress=False))
    track = read_track(tmp_path / "cut")
    assert [r.frame_index for r in track.records] == list(range(10))
    assert all(c is not None for c in track.cameras.values())
    assert len(list((tmp_path / "cut" / "cameras").glob("camera_*.json"))) == 10


def _detector():
    from broadtrack_graph.detect.weightfree import WeightFreeDetector

    return WeightFreeDetector()


def test_corrupt_frames_and_no_pitch_stretch_then_resume(clip, tmp_path):
    broken = tmp_path / "broken"
    shutil.copytree(clip, broken)
    images = sorted((broken / "img1").glob("*.jpg"))
    images[6].write_bytes(images[6].read_bytes()[:2000])  # truncated JPEG
    import cv2

    crowd = cv2.imread(str(images[0]))
    crowd[:] = (40, 40, 160)  # a cut-away: no grass at all
    for path in images[9:13]:
        cv2.imwrite(str(path), crowd)
    track_input(broken, tmp_path / "run", TrackingConfig(), progress=False)
    records = read_track(tmp_path / "run").records
    status = {r.frame_index: r.status for r in records}
    assert status[6] == "missing-frame"
    # The cut-away (no grass) is another view: no camera, status other-view.
    assert all(status[i] == "other-view" for i in range(9, 13))
    # One lost frame: tracked through (no flow link); after the cut-away: re-initialised.
    assert status[7] == "tracked" and status[13] == "reinitialised"
    assert all(status[i] in ("tracked", "reinitialised") for i in range(13, FRAMES))
    report = jac5(clip, tmp_path / "run")
    jac = {int(frame_id) - 1: row["jac"]["5"] for frame_id, row in report["per_frame"].items()}
    assert np.mean([jac[i] for i in (7, 8)]) >= 0.9
    assert np.mean([jac[i] for i in range(13, FRAMES)]) >= 0.9


def test_tracking_from_a_detections_file_alone(clip, tmp_path):
    annotations = read_annotations(clip / "annotations")
    path = tmp_path / "lines.jsonl"
    with DetectionsWriter(path) as writer:
        for index, (frame_id, lines) in enumerate(sorted(annotations.frames.items())):
            if index == 5:
                continue  # a frame without detections is carried on the motion prior, no camera claimed
            writer.write(annotations_to_observations(lines, index, 1920, 1080), frame_id=frame_id)
    track_input(None, tmp_path / "file", TrackingConfig(mode="fixed-lag", lag_frames=5), detections_path=path,
                progress=False)
    records = read_track(tmp_path / "file").records
    assert len(records) == FRAMES
    assert records[5].status == "motion-prior" and "no detections" in records[5].reason
    assert records[5].camera is None and records[6].camera is not None  # the track goes on after it
    report = jac5(clip, tmp_path / "file")
    assert report["completeness"] == (FRAMES - 1) / FRAMES and report["accuracy"] >= 0.85


def test_unreadable_inputs_are_one_line_errors(tmp_path):
    bad_video = tmp_path / "clip.mp4"
    bad_video.write_bytes(b"not a video")
    with pytest.raises(InputError) as info:
        track_input(bad_video, tmp_path / "out", progress=False)
    assert "clip.mp4" in str(info.value) and "\n" not in str(info.value)
    with pytest.raises(InputError, match="not found"):
        track_input(tmp_path / "nowhere", tmp_path / "out", progress=False)


def test_a_rerun_clears_what_the_earlier_run_left(tmp_path):
    out = tmp_path / "run"
    (out / "pass1" / "cameras").mkdir(parents=True)
    (out / "cameras").mkdir()
    (out / "cameras" / "camera_000099.json").write_text("{}", encoding="utf-8")
    for name in ("tripod.json", "shots.json", "notes.txt"):
        (out / name).write_text("{}", encoding="utf-8")
    result = run_frames([], 960, 540, out, RunContext(TrackingConfig(), progress=False))
    assert sorted(p.name for p in out.iterdir()) == ["cameras", "notes.txt", "summary.json", "track.jsonl"]
    assert list((out / "cameras").iterdir()) == [] and result.summary["frames_written"] == 0


def test_the_court_model_places_the_first_frame_before_the_field_model_and_the_search(clip, tmp_path):
    run = track_input(clip, tmp_path / "court", TrackingConfig(mode="online"), end=6, progress=False)
    counts = run.summary["reinit_searches"]
    assert counts["court_used"] == 1 and counts["model_tried"] == 0 and counts["global"] == 0
    assert jac5(clip, tmp_path / "court")["accuracy"] >= 0.9


def test_the_shipped_field_model_places_the_first_frame_without_the_global_search(clip, tmp_path):
    with_model = track_input(clip, tmp_path / "model", TrackingConfig(mode="online", reinit_model="shipped",
                                                                      court_reinit=False), end=6, progress=False)
    without = track_input(clip, tmp_path / "search", TrackingConfig(mode="online", reinit_model="none",
                                                                    court_reinit=False), end=6, progress=False)
    assert with_model.summary["reinit_searches"]["model_used"] == 1
    assert with_model.summary["reinit_searches"]["global"] == 0 and without.summary["reinit_searches"]["global"] == 1
    assert with_model.summary["timings_s"]["reinit_s"] < without.summary["timings_s"]["reinit_s"]
    for run in ("model", "search"):
        assert jac5(clip, tmp_path / run)["accuracy"] >= 0.9


@pytest.mark.parametrize("mode", ["online", "fixed-lag", "batch"])
def test_a_repeated_image_carries_the_estimate_of_the_frame_it_repeats(clip, tmp_path, mode):
    # A frame-rate conversion shows some images twice or three times: those frames carry the estimate of the frame
    # they repeat (whatever the pass made of it) and are not solved; the other frames track as before.
    repeated = tmp_path / "repeated"
    shutil.copytree(clip, repeated)
    images = sorted((repeated / "img1").glob("*.jpg"))
    for copy, source in ((5, 4), (10, 9), (11, 9)):
        shutil.copyfile(images[source], images[copy])
    result = track_input(repeated, tmp_path / mode, TrackingConfig(mode=mode), progress=False)
    records = {r.frame_index: r for r in read_track(tmp_path / mode).records}
    assert len(records) == FRAMES and result.summary["frames_with_camera"] == FRAMES
    for copy, source in ((5, 4), (10, 9), (11, 9)):
        assert records[copy].repeat_of == source and records[copy].status == "tracked"
        assert np.array_equal(records[copy].camera.to_vector(), records[source].camera.to_vector())
    assert all(records[i].repeat_of is None for i in records if i not in (5, 10, 11))
    report = jac5(clip, tmp_path / mode)
    jac = {int(frame_id) - 1: row["jac"]["5"] for frame_id, row in report["per_frame"].items()}
    assert np.mean([jac[i] for i in range(FRAMES) if i not in (5, 10, 11)]) >= 0.9
