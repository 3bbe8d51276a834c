"""Offline recovery: frames that cannot lock forward get cameras from their first good neighbour (backwards)."""

from __future__ import annotations

import json

import numpy as np
import pytest

import broadtrack_graph.reinit.frame as reinit_frame
from broadtrack_graph.actions.track import track_input
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.io.run_folder import read_track
from broadtrack_graph.reinit.scoring import ReinitResult
from broadtrack_graph.synth.motion import generate_camera_track
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.recover import recoverable_gaps

W, H = 960, 540
FRAMES, BLIND = 24, 6


@pytest.fixture()
def clip(tmp_path):
    """A detections file of noise-free keypoints of a synthetic main-camera pan (k1 0), and its cameras."""
    pitch = PitchTemplate()
    cameras = [c.replace(k1=0.0) for c in generate_camera_track("main", FRAMES, W, H, seed=3).cameras]
    names = sorted(n for n in pitch.keypoints if abs(pitch.keypoints[n][2]) < 1e-9)
    points = pitch.keypoint_array(names)
    path = tmp_path / "detections.jsonl"
    with path.open("w") as handle:
        for index, camera in enumerate(cameras):
            uv, front = camera.project(points)
            keep = front & camera.in_image(uv)
            entries = [{"name": names[k], "xy": uv[k].round(3).tolist(), "confidence": 0.9} for k in np.flatnonzero(keep)]
            handle.write(json.dumps({"frame": index, "image_size": [W, H], "units": "px", "keypoints": entries}) + "\n")
    return path, cameras


@pytest.fixture()
def blind_opening(monkeypatch):
    """Keypoint re-initialisation fails on its first BLIND calls (the opening cannot lock forward)."""
    original = reinit_frame.reinit_from_keypoints
    calls = {"n": 0}

    def failing(*args, **kwargs):
        calls["n"] += 1
        if calls["n"] <= BLIND:
            return ReinitResult(None, None, "", "blinded for the test")
        return original(*args, **kwargs)

    monkeypatch.setattr(reinit_frame, "reinit_from_keypoints", failing)
    return calls


def _cameras(run_dir):
    return [r.camera for r in read_track(run_dir).records]


def test_online_stays_causal_and_leaves_the_opening_without_camera(clip, blind_opening, tmp_path):
    path, _ = clip
    track_input(None, tmp_path / "online", TrackingConfig(mode="online"), detections_path=path, progress=False)
    cameras = _cameras(tmp_path / "online")
    assert all(c is None for c in cameras[:BLIND]) and all(c is not None for c in cameras[BLIND:])


@pytest.mark.parametrize("mode", ["fixed-lag", "batch"])
def test_offline_modes_recover_the_opening_backwards(clip, blind_opening, tmp_path, mode):
    path, truth = clip
    run = tmp_path / mode
    result = track_input(None, run, TrackingConfig(mode=mode, lag_frames=5), detections_path=path, progress=False)
    cameras = _cameras(run)
    assert all(c is not None for c in cameras), [i for i, c in enumerate(cameras) if c is None]
    assert result.summary["completeness"] == 1.0
    assert result.summary["offline_recovery"]["recovered_frames"] == BLIND
    records = read_track(run).records
    assert all("recovered offline" in (r.reason or "") for r in records[:BLIND])
    names = sorted(n for n in PitchTemplate().keypoints if abs(PitchTemplate().keypoints[n][2]) < 1e-9)
    points = PitchTemplate().keypoint_array(names)
    for camera, true in zip(cameras[:BLIND], truth[:BLIND]):
        uv, front = true.project(points)
        seen = front & true.in_image(uv)
        est, _ = camera.project(points[seen])
        assert 0.0 <= np.median(np.linalg.norm(est - uv[seen], axis=1)) < 2.0


def test_recovery_off_keeps_the_gap(clip, blind_opening, tmp_path):
    path, _ = clip
    track_input(None, tmp_path / "off", TrackingConfig(mode="fixed-lag", lag_frames=5, recover_max_frames=0),
                detections_path=path, progress=False)
    assert sum(c is None for c in _cameras(tmp_path / "off")) == BLIND


def test_recoverable_gaps_need_a_good_neighbour_and_known_observations():
    from broadtrack_graph.geometry.camera import Camera
    from broadtrack_graph.types.track_record import TrackRecord

    cam = Camera.from_degrees(1000, 0, 0, 70, 0, (0, 55, -12), W, H)
    status = ["failed", "failed", "tracked", "failed", "missing-frame", "failed", "tracked"]
    records = [TrackRecord(i, str(i), None, cam if s == "tracked" else None, status=s) for i, s in enumerate(status)]
    observations = {i: object() for i in range(7)}
    assert recoverable_gaps(records, observations, 10) == [(0, 2), (3, 4), (5, 6)]
    assert recoverable_gaps(records, observations, 1) == [(3, 4), (5, 6)]
    del observations[5]
    assert recoverable_gaps(records, observations, 10) == [(0, 2), (3, 4)]
