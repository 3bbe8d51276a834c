"""Frames shared by the re-initialisation tests."""

from __future__ import annotations

import pytest

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
