"""TrackRecord: validation, its track.jsonl object and back, standard deviations from a covariance."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.io.track_record import record_from_json, record_to_json
from broadtrack_graph.types.status import FrameStatus
from broadtrack_graph.types.track_record import TrackRecord, std_from_covariance

W, H = 1920, 1080


def camera(t: int) -> Camera:
    return Camera.from_degrees(2000 + 10 * t, -0.03 + 0.001 * t, 5 + 0.5 * t, 75 - 0.1 * t, 0.2, (0.5 * t, 55, -15), W, H)


def test_json_round_trip():
    std = {"pan_std_deg": 0.02, "focal_std_px": 3.5, "position_std_m": np.array([0.1, np.nan, 0.3])}
    record = TrackRecord(7, "000008", 0.28, camera(7), std, 0.75, True, active_factors=["lines", "flow"])
    data = json.loads(json.dumps(record_to_json(record, "cameras/camera_000008.json"), allow_nan=False))
    assert data["camera_file"] == "cameras/camera_000008.json"
    assert data["position_std_m"] == [0.1, None, 0.3] and data["tilt_std_deg"] is None
    back = record_from_json(data, W, H)
    assert np.allclose(back.camera.to_vector(), record.camera.to_vector(), atol=1e-12, rtol=0)
    assert (back.frame_index, back.frame_id, back.time_s, back.confidence, back.reinitialised) == (7, "000008", 0.28, 0.75, True)
    assert back.active_factors == ("lines", "flow") and set(back.std) == {"pan_std_deg", "focal_std_px", "position_std_m"}
    assert np.isnan(back.std["position_std_m"][1])
    empty = record_from_json(record_to_json(TrackRecord(2, "3", None, None, status=FrameStatus.NO_PITCH, reason="dark")), W, H)
    assert (empty.camera, empty.status, empty.reason) == (None, FrameStatus.NO_PITCH, "dark")
    with pytest.raises(ValueError, match="bad track record"):
        record_from_json({"frame_id": "1"}, W, H)


def test_record_validation():
    with pytest.raises(ValueError, match="status 'tracked' with camera=None"):
        TrackRecord(0, "1", 0.0, None)
    with pytest.raises(ValueError, match="status 'no-pitch' with camera=set"):
        TrackRecord(0, "1", 0.0, camera(0), status=FrameStatus.NO_PITCH)
    with pytest.raises(ValueError, match="unknown status"):
        TrackRecord(0, "1", 0.0, None, status="lost")
    with pytest.raises(ValueError, match="unknown std keys"):
        TrackRecord(0, "1", 0.0, camera(0), std={"pan_sigma": 1.0})


def test_std_from_covariance():
    variances = np.array([4.0, 1e-6, math.radians(0.1) ** 2, math.radians(0.2) ** 2, math.radians(0.3) ** 2, 0.01, 0.04, 0.09])
    covariance = np.diag(variances)
    covariance[0, 2] = covariance[2, 0] = 1e-5  # off-diagonal terms do not matter
    std = std_from_covariance(covariance)
    assert std["focal_std_px"] == pytest.approx(2.0)
    assert std["k1_std"] == pytest.approx(1e-3)
    assert (std["pan_std_deg"], std["tilt_std_deg"], std["roll_std_deg"]) == pytest.approx((0.1, 0.2, 0.3))
    assert np.allclose(std["position_std_m"], [0.1, 0.2, 0.3])
    TrackRecord(0, "1", 0.0, camera(0), std=std)  # accepted as a record's std
    with pytest.raises(ValueError, match=r"expected \(8, 8\)"):
        std_from_covariance(np.eye(6))


def test_a_repeated_frame_carries_its_source_and_says_so():
    source = TrackRecord(4, "000005", 0.16, camera(4), {"pan_std_deg": 0.02}, 0.81, True,
                         FrameStatus.REINITIALISED, None, ("lines",), "main")
    repeat = source.repeated_at(5, "000006", 0.2)
    assert (repeat.frame_index, repeat.frame_id, repeat.time_s, repeat.repeat_of) == (5, "000006", 0.2, 4)
    assert repeat.camera is source.camera and repeat.confidence == 0.81 and repeat.camera_id == "main"
    assert repeat.status == FrameStatus.TRACKED and not repeat.reinitialised  # re-initialised at 4, not at 5
    assert repeat.reason == "the same image as frame 4"
    again = repeat.repeated_at(6, "000007", 0.24)  # a frame shown three times: all point at the first
    assert again.repeat_of == 4 and again.reason == "the same image as frame 4"
    data = json.loads(json.dumps(record_to_json(again)))
    assert data["repeat_of"] == 4 and record_from_json(data, W, H).repeat_of == 4
    assert record_from_json(record_to_json(source), W, H).repeat_of is None
    # A frame without a camera repeats as such, its reason kept.
    unplaced = TrackRecord(8, "000009", 0.32, None, status=FrameStatus.UNPLACED, reason="no camera found")
    assert unplaced.repeated_at(9, "000010", 0.36).reason == "the same image as frame 8: no camera found"


def test_a_pass_that_changes_a_source_changes_its_repeats():
    from dataclasses import replace

    from broadtrack_graph.types.track_record import carry_repeats

    first = TrackRecord(0, "000001", 0.0, camera(0), {}, 0.9)
    records = [first, first.repeated_at(1, "000002", 0.04), TrackRecord(2, "000003", 0.08, camera(2), {}, 0.9)]
    refined = [replace(records[0], camera=camera(1)), records[1], records[2]]  # the refinement moved frame 0
    carried = carry_repeats(refined)
    assert carried[1].camera is carried[0].camera and carried[1].repeat_of == 0 and carried[1].frame_index == 1
    assert carried[2] is records[2]
