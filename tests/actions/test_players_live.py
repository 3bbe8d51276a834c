"""``track --players`` locates the players as the run writes its records: players.jsonl mirrors track.jsonl frame by
frame, and the files a run ends with are those of the ``players`` command on the finished run folder."""

from __future__ import annotations

import json

import numpy as np
import pytest

import broadtrack_graph.actions.track as track_action
import broadtrack_graph.reinit.frame as reinit_frame
from broadtrack_graph.actions.players import players_from_run
from broadtrack_graph.actions.players_live import FolderPlayers, LivePlayers
from broadtrack_graph.actions.track import track_input
from broadtrack_graph.detect.player_ids import link_track_ids
from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.io.player_boxes import read_player_boxes
from broadtrack_graph.io.run_folder import read_track
from broadtrack_graph.io.track_writer import TrackWriter
from broadtrack_graph.reinit.scoring import ReinitResult
from broadtrack_graph.synth.motion import generate_camera_track
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.types.player_boxes import PlayerBoxes
from broadtrack_graph.types.status import FrameStatus
from broadtrack_graph.types.track_record import TrackRecord

W, H = 960, 540
FRAMES, PLAYERS, BLIND = 24, 6, 6


@pytest.fixture()
def clip(tmp_path):
    """A detections file (noise-free keypoints of a synthetic main-camera pan, k1 0, and the boxes of 6 players
    walking at 0.2 m per frame) and the same boxes as a MOT file with ids, plus three bad ones: a NaN box, a
    frame the clip does not have, a foot far above the horizon."""
    pitch = PitchTemplate()
    cameras = [c.replace(k1=0.0) for c in generate_camera_track("main", FRAMES, W, H, seed=3).cameras]
    names = sorted(n for n in pitch.keypoints if abs(pitch.keypoints[n][2]) < 1e-9)
    points = pitch.keypoint_array(names)
    mot = []
    with (tmp_path / "detections.jsonl").open("w") as handle:
        for index, camera in enumerate(cameras):
            uv, front = camera.project(points)
            keep = front & camera.in_image(uv)
            entries = [{"name": names[k], "xy": uv[k].round(3).tolist(), "confidence": 0.9} for k in np.flatnonzero(keep)]
            boxes = []
            for tid in range(1, PLAYERS + 1):
                (u, v), = camera.project(np.array([[-52.0 + 4 * tid + 0.2 * index, -25.0 + 5 * tid, 0.0]]))[0]
                boxes.append([round(u - 8, 2), round(v - 40, 2), round(u + 8, 2), round(v, 2)])
                mot.append(f"{index + 1},{tid},{u - 8:.2f},{v - 40:.2f},16,40,1")
            handle.write(json.dumps({"frame": index, "image_size": [W, H], "units": "px", "keypoints": entries,
                                     "players": boxes}) + "\n")
    mot += ["40,1,100,100,20,50,1", "2,9,480,-5000,20,50,1", "3,5,nan,100,20,50,1"]
    (tmp_path / "boxes.txt").write_text("\n".join(mot) + "\n")
    return tmp_path / "detections.jsonl", tmp_path / "boxes.txt"


@pytest.fixture()
def blind_opening(monkeypatch):
    """Keypoint re-initialisation fails on its first BLIND calls: the forward pass loses the opening, the offline
    recovery gives it cameras afterwards (fixed-lag rewrites the run folder)."""
    original = reinit_frame.reinit_from_keypoints
    calls = {"n": 0}

    def failing(*args, **kwargs):
        calls["n"] += 1
        return ReinitResult(None, None, "", "blinded") if calls["n"] <= BLIND else original(*args, **kwargs)

    monkeypatch.setattr(reinit_frame, "reinit_from_keypoints", failing)


def _lines(path):
    text = path.read_text()
    assert text == "" or text.endswith("\n"), "a partial last line"
    return [json.loads(line) for line in text.splitlines()]


def assert_same_lines(got, want, tol=1e-9):
    """Same players.jsonl objects, in order: equal keys and strings, numbers within tol."""
    assert len(got) == len(want)

    def close(a, b):
        if isinstance(a, (int, float)) and isinstance(b, (int, float)) and not isinstance(a, bool):
            return abs(a - b) <= tol
        if isinstance(a, list) and isinstance(b, list):
            return len(a) == len(b) and all(close(x, y) for x, y in zip(a, b))
        return a == b

    for a, b in zip(got, want):
        assert a.keys() == b.keys() and all(close(a[k], b[k]) for k in a), (a, b)


def assert_matches_the_players_command(run, boxes, after):
    """run's players files are those ``players RUN --boxes FILE`` writes from the finished run folder."""
    players_from_run(run, boxes, after, progress=False)
    assert_same_lines(_lines(run / "players.jsonl"), _lines(after / "players.jsonl"))
    assert json.loads((run / "predictions-gamestate.json").read_text()) == \
        json.loads((after / "predictions-gamestate.json").read_text())
    got, want = (json.loads((d / "players_summary.json").read_text()) for d in (run, after))
    assert {**got, "run": None} == {**want, "run": None}
    return got


@pytest.mark.parametrize("mode", ["online", "fixed-lag", "batch"])
def test_players_end_as_the_players_command_writes_them(clip, tmp_path, mode):
    detections, boxes = clip
    run = tmp_path / "run"
    result = track_input(None, run, TrackingConfig(mode=mode, lag_frames=5), detections_path=detections,
                         progress=False, players=boxes)
    summary = assert_matches_the_players_command(run, boxes, tmp_path / "after")
    assert result.summary["players"]["boxes"] == FRAMES * PLAYERS + 2
    assert result.summary["players"]["located"] == FRAMES * PLAYERS
    # the bad input: one line each, skipped (the NaN box, the unknown frame, the foot above the horizon)
    assert summary["issue_count"] == 3 and all("\n" not in issue for issue in summary["issues"])
    assert sum("not finite or empty" in i for i in summary["issues"]) == 1
    assert sum("index 39 is not in the run" in i for i in summary["issues"]) == 1
    assert sum("above the horizon" in i for i in summary["issues"]) == 1
    positions = [line for line in _lines(run / "players.jsonl") if line["x_m"] is not None]
    assert len(positions) == FRAMES * PLAYERS
    for line in positions:  # the true foot point (cameras from noise-free keypoints)
        truth = (-52.0 + 4 * line["track_id"] + 0.2 * line["frame"], -25.0 + 5 * line["track_id"])
        assert np.hypot(line["x_m"] - truth[0], line["y_m"] - truth[1]) < 0.05
    if mode == "batch":  # the provisional players of the online first pass sit beside its track (players.jsonl only)
        players_from_run(run / "pass1", boxes, tmp_path / "after1", progress=False)
        assert_same_lines(_lines(run / "pass1" / "players.jsonl"), _lines(tmp_path / "after1" / "players.jsonl"))
        assert not (run / "pass1" / "predictions-gamestate.json").exists()


def test_online_players_are_written_with_each_record(clip, tmp_path, monkeypatch):
    detections, boxes = clip
    run = tmp_path / "run"
    checked = []
    original = FolderPlayers.record_written

    def record_written(self, record, line):
        original(self, record, line)
        written = [json.loads(t)["frame"] for t in (run / "track.jsonl").read_text().splitlines()]
        located = sorted({p["frame"] for p in _lines(run / "players.jsonl")})
        assert located == written  # every frame of the clip has boxes
        checked.append(record.frame_index)

    monkeypatch.setattr(FolderPlayers, "record_written", record_written)
    track_input(None, run, TrackingConfig(mode="online"), detections_path=detections, progress=False, players=boxes)
    assert checked == list(range(FRAMES))


def test_fixed_lag_rewrite_rewrites_the_players_from_the_final_cameras(clip, blind_opening, tmp_path, monkeypatch):
    detections, boxes = clip
    run = tmp_path / "run"
    folders = []
    original = LivePlayers.observer_for

    def observer_for(self, folder, width_px, height_px):
        folders.append(folder)
        return original(self, folder, width_px, height_px)

    monkeypatch.setattr(LivePlayers, "observer_for", observer_for)
    result = track_input(None, run, TrackingConfig(mode="fixed-lag", lag_frames=5), detections_path=detections,
                         progress=False, players=boxes)
    assert folders == [run, run]  # the forward pass, then the rewrite after the offline recovery
    assert result.summary["offline_recovery"]["recovered_frames"] == BLIND
    assert_matches_the_players_command(run, boxes, tmp_path / "after")
    recovered = [line for line in _lines(run / "players.jsonl") if line["frame"] < BLIND]
    assert len(recovered) == BLIND * PLAYERS + 1 and all(line["camera_status"] != "failed" for line in recovered)
    assert sum(line["x_m"] is not None for line in recovered) == BLIND * PLAYERS


def _interrupt_at(frames, index):
    for frame in frames:
        if frame.frame_index == index:
            raise KeyboardInterrupt
        yield frame


@pytest.mark.parametrize("mode", ["online", "fixed-lag"])
def test_an_interrupted_run_keeps_the_players_of_every_frame_it_wrote(clip, tmp_path, monkeypatch, mode):
    detections, boxes = clip
    run = tmp_path / "run"
    run.mkdir()
    for stale in ("predictions-gamestate.json", "players_summary.json", "players.jsonl"):
        (run / stale).write_text("{}")  # an earlier run's: must not pass for this run's
    original = track_action.frames_from_detections
    monkeypatch.setattr(track_action, "frames_from_detections",
                        lambda *args, **kwargs: _interrupt_at(original(*args, **kwargs), 10))
    with pytest.raises(KeyboardInterrupt):
        track_input(None, run, TrackingConfig(mode=mode, lag_frames=5), detections_path=detections, progress=False,
                    players=boxes)
    written = [r.frame_index for r in read_track(run).records]
    assert written == list(range(10 if mode == "online" else 10 - 5))
    lines = _lines(run / "players.jsonl")
    assert sorted({line["frame"] for line in lines}) == written
    assert not (run / "predictions-gamestate.json").exists() and not (run / "players_summary.json").exists()
    players_from_run(run, boxes, tmp_path / "after", progress=False)  # the interrupted run, after the fact
    assert_same_lines(lines, _lines(tmp_path / "after" / "players.jsonl"))


@pytest.mark.parametrize("mode", ["online", "batch"])
def test_detector_blobs_from_a_detections_file(clip, tmp_path, mode):
    detections, _ = clip
    run = tmp_path / "run"
    track_input(None, run, TrackingConfig(mode=mode), detections_path=detections, progress=False, players="detector")
    blobs = PlayerBoxes(source="detector", kind="detector")  # what the run collected, linked at the end
    for frame in read_player_boxes(detections).frames:
        blobs.add_frame(frame.frame_index, frame.frame_id, frame.boxes_px)
    linked = link_track_ids(blobs)
    assert_matches_the_players_command(run, linked, tmp_path / "after")
    ids = {line["track_id"] for line in _lines(run / "players.jsonl")}
    assert ids == set(range(PLAYERS))


@pytest.fixture(scope="module")
def image_clip(tmp_path_factory):
    from broadtrack_graph.synth.writer import write_synthetic_clip

    out = tmp_path_factory.mktemp("clip") / "main"
    write_synthetic_clip(out, preset="main", frame_count=10, width_px=W, height_px=H, seed=3, write_masks=False,
                         progress=False)
    return out


@pytest.mark.parametrize("mode, stop", [("online", 6), ("batch", None)])
def test_detector_blobs_of_image_input(image_clip, tmp_path, monkeypatch, mode, stop):
    """The detector's blobs come after the frame's record in online mode: the record waits for them."""
    run = tmp_path / "run"
    blobs = PlayerBoxes(source="detector", kind="detector")
    original = LivePlayers.frame_done

    def frame_done(self, frame, handed, detections):
        if detections is not None and detections.player_boxes_px is not None and len(detections.player_boxes_px):
            blobs.add_frame(frame.frame_index, frame.frame_id, detections.player_boxes_px)
        original(self, frame, handed, detections)

    monkeypatch.setattr(LivePlayers, "frame_done", frame_done)
    if stop is not None:
        source_frames = track_action.frames_from_source
        monkeypatch.setattr(track_action, "frames_from_source", lambda s: _interrupt_at(source_frames(s), stop))
        with pytest.raises(KeyboardInterrupt):
            track_input(image_clip, run, TrackingConfig(mode=mode), progress=False, players="detector")
        assert [r.frame_index for r in read_track(run).records] == list(range(stop))
        players_from_run(run, link_track_ids(blobs), tmp_path / "after", progress=False)
        lines = _lines(run / "players.jsonl")
        assert_same_lines(lines, _lines(tmp_path / "after" / "players.jsonl"))
        assert sorted({line["frame"] for line in lines}) == list(range(stop))
    else:
        track_input(image_clip, run, TrackingConfig(mode=mode), progress=False, players="detector")
        assert_matches_the_players_command(run, link_track_ids(blobs), tmp_path / "after")
        assert len(_lines(run / "players.jsonl")) == blobs.box_count > 10 * 5


def _id_and_index_run(tmp_path, records=6):
    """A box file whose frames carry ids and indices (see below) and a live run of `records` records written by
    hand (ids 000001.., record 3 without a camera); returns (LivePlayers, run folder, box file)."""
    frames = [(1, "B"), (2, "000005"), (3, None), (0, "000001"), (9, "Z")]
    boxes = tmp_path / "boxes.jsonl"
    with boxes.open("w") as handle:
        for index, frame_id in frames:
            entry = {"frame": index, "image_size": [W, H], "players": [[400, 300, 420, 360], [600, 320, 616, 380]]}
            if frame_id is not None:
                entry["frame_id"] = frame_id
            handle.write(json.dumps(entry) + "\n")
    std = {"pan_std_deg": 0.02, "focal_std_px": 4.0, "position_std_m": np.array([0.1, 0.1, 0.1])}
    live = LivePlayers(boxes)
    run = tmp_path / "run"
    live.start(W, H, run)
    with TrackWriter(run, W, H, on_write=live.observer_for(run, W, H)) as writer:
        for k in range(records):
            if k == 3:
                writer.write(TrackRecord(k, f"{k + 1:06d}", k / 25, None, status=FrameStatus.NO_PITCH, reason="no grass"))
            else:
                camera = Camera.from_degrees(1200.0, 0.0, -20.0 + k, 74.0, 0.0, [0.0, 55.0, -15.0], W, H)
                writer.write(TrackRecord(k, f"{k + 1:06d}", k / 25, camera, std))
            if k == 4:  # the box frame "000005" (index 2) came with record 4; "B" (index 1) still waits for its id
                assert [line["frame"] for line in _lines(run / "players.jsonl")] == [0, 0, 3, 3, 4, 4]
    return live, run, boxes


def test_box_frames_match_by_id_else_by_index(tmp_path):
    """A box frame is matched by its id; one whose index the run wrote under another id is located at the end of
    the pass when its id never comes; frames the run never wrote are reported."""
    live, run, boxes = _id_and_index_run(tmp_path)
    result = live.finish(run, progress=False)
    got = _lines(run / "players.jsonl")
    assert [line["frame"] for line in got] == [0, 0, 3, 3, 4, 4, 1, 1]  # "B" with the record of its index, at the end
    players_from_run(run, boxes, tmp_path / "after", progress=False)
    want = _lines(tmp_path / "after" / "players.jsonl")
    key = lambda line: (line["frame"], line["box_px"])  # noqa: E731
    assert_same_lines(sorted(got, key=key), sorted(want, key=key))
    assert json.loads((run / "predictions-gamestate.json").read_text()) == \
        json.loads((tmp_path / "after" / "predictions-gamestate.json").read_text())
    assert (result.boxes, result.located, result.no_camera) == (10, 6, 2)
    assert result.issues == [f"{boxes}: frame Z is not in the run; its 2 box(es) skipped"]


def test_a_stopped_run_locates_the_frames_waiting_for_their_id(tmp_path):
    live, run, boxes = _id_and_index_run(tmp_path, records=5)
    live.close()  # what track_input does when the run is interrupted
    got = _lines(run / "players.jsonl")
    assert [line["frame"] for line in got] == [0, 0, 3, 3, 4, 4, 1, 1]
    players_from_run(run, boxes, tmp_path / "after", progress=False)
    assert sorted(line["frame"] for line in _lines(tmp_path / "after" / "players.jsonl")) == [0, 0, 1, 1, 3, 3, 4, 4]
    assert not (run / "predictions-gamestate.json").exists()


def test_a_bad_box_file_fails_before_tracking(clip, tmp_path):
    detections, _ = clip
    with pytest.raises(InputError, match="player box file not found"):
        track_input(None, tmp_path / "run", TrackingConfig(mode="online"), detections_path=detections,
                    progress=False, players=tmp_path / "missing.txt")
    assert not (tmp_path / "run" / "track.jsonl").exists()
