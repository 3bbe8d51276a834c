"""Frames and keypoints shared by the re-initialisation tests."""

from __future__ import annotations

import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate


@pytest.fixture(scope="module")
def main_frame():
    """A rendered first frame of the `main` preset at 1280x720: its true camera and its weight-free detections."""
    from broadtrack_graph.detect.weightfree import WeightFreeDetector
    from broadtrack_graph.synth.clip import render_clip
    from broadtrack_graph.synth.motion import generate_camera_track

    track = generate_camera_track("main", 1, 1280, 720, seed=0)
    frame = render_clip("main", 1, 1280, 720, seed=0, cameras=[track.cameras[0]]).frames[0]
    return frame.camera, WeightFreeDetector(PitchTemplate()).detect(frame.image)


@pytest.fixture(scope="module")
def broadcast_keypoints():
    """A roll-free main camera at 1280x720 (tripod (-0.7, 65.9, -13.9) m, f 1480 px) and its ground keypoints in view:
    (camera, uv_px (N, 2), points_w (N, 3))."""
    camera = Camera.from_degrees(1480.0, 0.0, -43.0, 84.0, 0.0, (-0.7, 65.9, -13.9), 1280, 720)
    pitch = PitchTemplate()
    points_w = pitch.keypoint_array([n for n in pitch.keypoints if abs(pitch.keypoints[n][2]) < 1e-9])
    uv, front = camera.project(points_w)
    seen = front & camera.in_image(uv)
    assert seen.sum() >= 10
    return camera, uv[seen], points_w[seen]


@pytest.fixture
def one_opencv_thread():
    """OpenCV on one thread, as ``bench placements`` runs it (with the tracker's template, ``fitting_curves``): its
    filters' sums in another order move a marking point by a hair, which can change which of two hypotheses tied on
    the map is fitted first."""
    import cv2

    threads = cv2.getNumThreads()
    cv2.setNumThreads(1)
    yield
    cv2.setNumThreads(threads)
