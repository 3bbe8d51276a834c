"""Fixtures of the benchmark tests."""

from __future__ import annotations

import json
import shutil

import cv2
import numpy as np
import pytest

from broadtrack_graph.cli import main
from broadtrack_graph.synth.writer import write_synthetic_clip


@pytest.fixture
def bench_real_video_section(tmp_path):
    """``run(*options) -> (the report's video section, the runs' folder)``: ``bench real --video-dir`` on a folder
    holding one 8-frame rendered main-camera clip (``main.mp4``, 640x360), with ``options`` added."""

    def run(*options: str):
        clip = tmp_path / "clip"
        write_synthetic_clip(clip, preset="main", frame_count=8, width_px=640, height_px=360, seed=3, write_mp4=True,
                             write_masks=False, progress=False)
        videos = tmp_path / "videos"
        videos.mkdir(exist_ok=True)
        shutil.copy(clip / "clip.mp4", videos / "main.mp4")
        report_path, runs = tmp_path / "report.json", tmp_path / "runs"
        assert main(["bench", "real", "--video-dir", str(videos), *options, "--out", str(runs), "--no-overlay",
                     "--no-progress", "--json", str(report_path)]) == 0
        return json.loads(report_path.read_text())["sections"]["video"], runs / "video"

    return run


@pytest.fixture
def grey_video(tmp_path):
    """``make(width, height, frames, level) -> path``: an mp4v video of ``frames`` uniform frames of grey ``level``."""

    def make(width: int, height: int, frames: int, level: int):
        video = tmp_path / "grey.mp4"
        writer = cv2.VideoWriter(str(video), cv2.VideoWriter_fourcc(*"mp4v"), 25.0, (width, height))
        for _ in range(frames):
            writer.write(np.full((height, width, 3), level, np.uint8))
        writer.release()
        return video

    return make


@pytest.fixture
def read_video():
    """``read(path) -> [frames]``: every frame a video decodes to, BGR uint8, in order."""

    def read(path) -> list:
        capture = cv2.VideoCapture(str(path))
        frames = []
        while True:
            ok, image = capture.read()
            if not ok:
                break
            frames.append(image)
        capture.release()
        return frames

    return read
