"""Shots in whole runs (broadtrack_graph.track.shot_stream, track.passes): a clip of other views only."""

from __future__ import annotations

import json

import numpy as np

from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.inputs import FrameInput
from broadtrack_graph.track.passes import run_frames
from broadtrack_graph.track.run_context import RunContext


def test_a_clip_of_crowd_only_writes_no_camera_and_says_so(tmp_path):
    """The court model looks at the frames read as another view (their markings might fix a camera): none here."""
    from broadtrack_graph.detect.weightfree import WeightFreeDetector

    rng = np.random.default_rng(0)
    frames = []
    for i in range(8):
        image = rng.integers(0, 255, (90, 160, 3)).astype(np.uint8)
        image[..., 1] //= 3  # stands: little green
        frames.append(FrameInput(i, f"{i + 1:06d}", i / 25.0, image=image))
    result = run_frames(frames, 160, 90, tmp_path / "run", RunContext(TrackingConfig(mode="online"),
                                                                      WeightFreeDetector(), progress=False))
    assert result.summary["note"].startswith("no shot of a pitch camera")
    assert result.summary["status_counts"]["other-view"] == 8
    records = [json.loads(line) for line in (tmp_path / "run" / "track.jsonl").read_text().splitlines()]
    assert all(r["reason"].startswith("other view (crowd)") for r in records)
    assert not any((tmp_path / "run" / "cameras").glob("*.json"))
    shots = json.loads((tmp_path / "run" / "shots.json").read_text())["shots"]
    assert [(s["start"], s["end"], s["kind"], s["camera_id"]) for s in shots] == [(0, 8, "crowd", None)]


def test_the_detector_s_working_image_is_made_once_and_the_thumbnails_come_from_it():
    from broadtrack_graph.track.shot_stream import ShotStream

    rng = np.random.default_rng(1)
    made = []

    def reduce(image):
        made.append(image.shape)
        return image[::2, ::2].copy() if image.shape[1] >= 320 else None

    frames = [FrameInput(i, f"{i + 1:06d}", i / 25.0, image=rng.integers(0, 255, (h, w, 3)).astype(np.uint8))
              for i, (h, w) in enumerate([(180, 320), (180, 320), (90, 160)])]
    frames.append(FrameInput(3, "000004", 0.12))  # a missing frame passes through
    out = list(ShotStream(frames, reduce=reduce))
    assert made == [(180, 320, 3), (180, 320, 3), (90, 160, 3)]
    assert out[0].working_bgr.shape == (90, 160, 3) and out[2].working_bgr is None and out[3].working_bgr is None
    assert all(frame.shot is not None for frame in out[:3])
