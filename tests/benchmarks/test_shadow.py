"""``bench real --shadow``: a stand's shadow laid over frames, and the video section tracking the shaded copy."""

from __future__ import annotations

import numpy as np
import pytest

from broadtrack_graph.benchmarks.shadow import SHADOW_EDGE, lay_shadow, shadow_map, write_shadowed
from broadtrack_graph.errors import InputError


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


def test_the_shaded_copy_of_a_video_has_every_frame(tmp_path, grey_video, read_video):
    video = grey_video(160, 96, 5, 200)
    out = tmp_path / "out" / "grey-shadow.mp4"
    assert write_shadowed(video, out, 0.5) == 5
    frames = read_video(out)
    assert len(frames) == 5 and frames[0].shape == (96, 160, 3)
    assert abs(frames[2][:, :40].mean() - 200) < 6 and abs(frames[2][:, 130:].mean() - 100) < 6
    with pytest.raises(InputError, match="share of light"):
        write_shadowed(video, tmp_path / "bad.mp4", 0.0)
    with pytest.raises(InputError) as missing:
        write_shadowed(tmp_path / "none.mp4", tmp_path / "bad.mp4", 0.5)
    assert "none.mp4" in str(missing.value)


def test_bench_real_tracks_the_shaded_copy_and_scores_it_on_the_unshaded_frames(bench_real_video_section):
    section, runs = bench_real_video_section("--shadow", "0.45")
    assert section["shadow_kept"] == 0.45 and list(section["clips"]) == ["main-shadow-0.45"]
    figures = section["clips"]["main-shadow-0.45"]
    assert figures["frames"] == 8 and figures["frames_with_camera"] >= 6
    assert (runs / "copies" / "main-shadow-0.45.mp4").is_file()
    assert (runs / "main-shadow-0.45" / "track.jsonl").is_file()
