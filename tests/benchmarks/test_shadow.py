"""``bench real --shadow``: a stand's shadow laid over frames, and the video section tracking the shaded copy."""

from __future__ import annotations

import json
import shutil

import cv2
import numpy as np
import pytest

from broadtrack_graph.benchmarks.shadow import SHADOW_EDGE, lay_shadow, shadow_map, write_shadowed
from broadtrack_graph.cli import main
from broadtrack_graph.errors import InputError
from broadtrack_graph.synth.writer import write_synthetic_clip


def test_the_shadow_keeps_its_share_of_the_light_right_of_a_soft_edge():
    image = np.full((120, 200, 3), 200, np.uint8)
    shaded = lay_shadow(image, 0.45)
    assert shaded.shape == image.shape and shaded.dtype == np.uint8
    middle = shaded[60, :, 0].astype(int)
    edge = int(SHADOW_EDGE[0] * 200)
    assert np.all(middle[: edge - 10] == 200) and np.all(np.abs(middle[edge + 10:] - 90) <= 1)
    assert np.all(np.diff(middle) <= 0) and 90 < middle[edge] < 200  # a soft edge, darker to the right
    # The edge leans: higher rows are lit further right.
    assert shaded[0, edge + 12, 0] > shaded[119, edge + 12, 0]
    np.testing.assert_array_equal(lay_shadow(image, 1.0), image)
    shade = shadow_map(200, 120)
    assert shade.shape == (120, 200, 1) and 0.0 <= shade.min() and shade.max() <= 1.0


def test_the_shaded_copy_of_a_video_has_every_frame(tmp_path):
    video = tmp_path / "grey.mp4"
    writer = cv2.VideoWriter(str(video), cv2.VideoWriter_fourcc(*"mp4v"), 25.0, (160, 96))
    for _ in range(5):
        writer.write(np.full((96, 160, 3), 200, np.uint8))
    writer.release()
    out = tmp_path / "out" / "grey-shadow.mp4"
    assert write_shadowed(video, out, 0.5) == 5
    capture = cv2.VideoCapture(str(out))
    frames = []
    while True:
        ok, image = capture.read()
        if not ok:
            break
        frames.append(image)
    assert len(frames) == 5 and frames[0].shape == (96, 160, 3)
    assert abs(frames[2][:, :40].mean() - 200) < 6 and abs(frames[2][:, 130:].mean() - 100) < 6
    with pytest.raises(InputError, match="share of light"):
        write_shadowed(video, tmp_path / "bad.mp4", 0.0)
    with pytest.raises(InputError) as missing:
        write_shadowed(tmp_path / "none.mp4", tmp_path / "bad.mp4", 0.5)
    assert "none.mp4" in str(missing.value)


def test_bench_real_tracks_the_shaded_copy_and_scores_it_on_the_unshaded_frames(tmp_path):
    clip = tmp_path / "clip"
    write_synthetic_clip(clip, preset="main", frame_count=8, width_px=640, height_px=360, seed=3, write_mp4=True,
                         write_masks=False, progress=False)
    videos = tmp_path / "videos"
    videos.mkdir()
    shutil.copy(clip / "clip.mp4", videos / "main.mp4")
    report_path = tmp_path / "report.json"
    assert main(["bench", "real", "--video-dir", str(videos), "--shadow", "0.45", "--out", str(tmp_path / "runs"),
                 "--no-overlay", "--no-progress", "--json", str(report_path)]) == 0
    section = json.loads(report_path.read_text())["sections"]["video"]
    assert section["shadow_kept"] == 0.45 and list(section["clips"]) == ["main-shadow-0.45"]
    figures = section["clips"]["main-shadow-0.45"]
    assert figures["frames"] == 8 and figures["frames_with_camera"] >= 6
    assert (tmp_path / "runs" / "video" / "copies" / "main-shadow-0.45.mp4").is_file()
    assert (tmp_path / "runs" / "video" / "main-shadow-0.45" / "track.jsonl").is_file()
