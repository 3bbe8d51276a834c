"""Per-frame ground-truth homographies (gt_homographies.json)."""

from __future__ import annotations

import json

import numpy as np
import pytest

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.gt_homographies import read_gt_homographies
from tests.conftest import SHARED_DATA


def test_reads_frames_and_size(tmp_path):
    path = tmp_path / "gt.json"
    H = [[10.0, 0.0, 640.0], [0.0, 10.0, 360.0], [0.0, 0.0, 1.0]]
    path.write_text(json.dumps({"image_size": [1280, 720], "clip": "x",
                                "frames": [{"frame": 0, "frame_id": "000001", "H_world_to_image": H},
                                           {"frame": 1, "H_world_to_image": H}]}))
    gt = read_gt_homographies(path)
    assert gt.image_size == (1280, 720) and sorted(gt.homographies) == [0, 1]
    assert np.allclose(gt.homographies[1], H) and gt.frame_ids == {0: "000001"} and gt.info == {"clip": "x"}


@pytest.mark.parametrize("content, message", [
    ({"frames": []}, "image_size"),
    ({"image_size": [10, 10], "frames": [{"frame": 0, "H_world_to_image": [[1, 2], [3, 4]]}]}, "3x3"),
    ({"image_size": [10, 10], "frames": [{"frame": 0}]}, "no numeric"),
    ({"image_size": [10, 10], "frames": []}, "no frame"),
])
def test_bad_files_give_one_line(tmp_path, content, message):
    path = tmp_path / "gt.json"
    path.write_text(json.dumps(content))
    with pytest.raises(InputError, match=message) as info:
        read_gt_homographies(path)
    assert "\n" not in str(info.value) and str(path) in str(info.value)


def test_reads_the_shared_clips():
    files = sorted((SHARED_DATA / "ts-worldcup-dev").glob("*/gt_homographies.json"))
    if not files:
        pytest.skip("TS-WorldCup ground truth not found beside the clone")
    for path in files:
        gt = read_gt_homographies(path)
        assert gt.image_size == (1280, 720) and len(gt.homographies) > 50
