"""The ``clip`` route of ``bench placements --random``: the pan, its frames, the judging of what the tracker wrote, and
one clip tracked end to end."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.benchmarks.placement_frames import draw_frame
from broadtrack_graph.benchmarks.random_clips import PAN_PX_PER_FRAME, clip_images, judged_clip, pan_cameras
from broadtrack_graph.benchmarks.random_placements import WRONG_PX
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.court_fit import twin_camera
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.types.track_record import TrackRecord

SEED, WIDTH, HEIGHT = 3, 640, 360
GROUND = np.vstack([p for name, p in PitchTemplate().sample_uniform(1.0).items()
                    if PitchTemplate().is_on_ground(name)])


def _record(index: int, camera, confidence: float | None = 0.9) -> TrackRecord:
    return TrackRecord(frame_index=index, frame_id=f"{index + 1:06d}", time_s=index / 25.0, camera=camera,
                       confidence=confidence, status="tracked" if camera is not None else "failed")


def test_the_pan_moves_the_image_centre_by_its_drawn_speed_every_frame():
    truth = draw_frame(SEED, 0, WIDTH, HEIGHT, ["clean"], "plain")["drawn"].camera
    cameras = pan_cameras(truth, 5, np.random.default_rng(1))
    assert len(cameras) == 5 and np.allclose(cameras[0].to_vector(), truth.to_vector())
    centre = truth.backproject(np.array([[WIDTH / 2.0, HEIGHT / 2.0]]))[0] * 100.0 + truth.position_m
    shifts = [np.linalg.norm(c.project(centre[None])[0][0] - (WIDTH / 2.0, HEIGHT / 2.0)) for c in cameras]
    steps = np.diff(shifts)
    assert PAN_PX_PER_FRAME[0] * 0.9 <= steps.mean() <= PAN_PX_PER_FRAME[1] * 1.1
    assert np.allclose(steps, steps.mean(), rtol=0.05)
    assert all(np.allclose(c.position_m, truth.position_m) and c.focal_px == truth.focal_px for c in cameras)


def test_a_clips_frames_start_with_the_single_frame_and_follow_the_pan():
    frame = draw_frame(SEED, 0, WIDTH, HEIGHT, ["clean"], "plain")
    cameras = pan_cameras(frame["drawn"].camera, 3, np.random.default_rng(2))
    images = clip_images(frame, cameras)
    assert len(images) == 3 and images[0] is frame["image"]
    assert all(image.shape == (HEIGHT, WIDTH, 3) for image in images)
    assert not np.array_equal(images[1], images[2])


def test_written_cameras_are_judged_against_their_own_frames_truth_or_its_twin():
    truth = draw_frame(SEED, 0, WIDTH, HEIGHT, ["clean"], "plain")["drawn"].camera
    cameras = pan_cameras(truth, 4, np.random.default_rng(3))
    right = [_record(0, None, None), _record(1, cameras[1]), _record(2, cameras[2]), _record(3, cameras[3])]
    judged = judged_clip(right, cameras, GROUND, 3.0, WRONG_PX)
    assert judged["outcome"] == "found" and not judged["twin"] and judged["first_written"] == 1
    assert (judged["written"], judged["right"], judged["near"], judged["wrong"]) == (3, 3, 0, 0)
    assert judged["error_px"] < 1e-6 and judged["confidence"] == 0.9
    # Frame 2's camera written on frame 3: off by a frame's pan (1-4 px), not right, not wrong.
    late = judged_clip([_record(3, cameras[2])], cameras, GROUND, 0.5, WRONG_PX)
    assert late["outcome"] == "near" and 0.5 < late["error_px"] <= 4.5
    twins = judged_clip([_record(k, twin_camera(c)) for k, c in enumerate(cameras)], cameras, GROUND, 3.0, WRONG_PX)
    assert twins["outcome"] == "wrong" and twins["twin"] and twins["right"] == 4
    # One wrong camera among right ones makes the clip wrong; nothing written is none.
    off = cameras[1].replace(tilt_rad=cameras[1].tilt_rad + np.radians(2.0))
    wrong = judged_clip([_record(0, cameras[0]), _record(1, off)], cameras, GROUND, 3.0, WRONG_PX)
    assert wrong["outcome"] == "wrong" and not wrong["twin"] and wrong["wrong"] == 1 and wrong["error_px"] > WRONG_PX
    assert judged_clip([_record(0, None, None)], cameras, GROUND, 3.0, WRONG_PX)["outcome"] == "none"


def test_one_clip_tracked_end_to_end(tmp_path):
    from broadtrack_graph.benchmarks.random_clips import clip_result

    # Frame 0 of seed 3 at 640x360, plain: a camera the court model finds on the single frame.
    frame = draw_frame(SEED, 0, WIDTH, HEIGHT, ["clean"], "plain")
    result = clip_result(SEED, 0, frame, 3, TrackingConfig(mode="online"), GROUND, 3.0, WRONG_PX)
    assert result["frames"] == 3 and result["written"] == 3 and result["first_written"] == 0
    assert result["outcome"] in ("found", "wrong") and result["right"] == 3 and result["error_px"] < 3.0
    assert result["seconds"] > 0.0 and result["right_under_bar"] is False
