import json

import numpy as np
import pytest

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.player_boxes import read_player_boxes
from broadtrack_graph.types.player_boxes import PlayerBoxes


def test_dispatch_by_file_kind(tmp_path):
    mot = tmp_path / "t.txt"
    mot.write_text("1,3,100,200,20,60,1\n")
    assert read_player_boxes(mot).kind == "mot"
    det = tmp_path / "d.jsonl"
    det.write_text(json.dumps({"frame": 4, "image_size": [1280, 720], "players": [[10, 20, 30, 80]]}) + "\n"
                   + "{broken\n" + json.dumps({"frame": 5, "image_size": [1280, 720]}) + "\n")
    boxes = read_player_boxes(det)
    assert boxes.kind == "detections" and boxes.frames[0].frame_index == 4
    assert boxes.frames[0].track_ids.tolist() == [-1]
    assert any("malformed" in issue for issue in boxes.issues)
    gs = tmp_path / "seq"
    gs.mkdir()
    (gs / "Labels-GameState.json").write_text(json.dumps({"images": [{"image_id": "1", "file_name": "000001.jpg"}],
        "annotations": [{"image_id": "1", "supercategory": "object", "track_id": 1,
                         "bbox_image": {"x": 1, "y": 2, "w": 3, "h": 4}}]}))
    assert read_player_boxes(gs).kind == "gamestate"
    with pytest.raises(InputError):
        read_player_boxes(tmp_path / "nothing.txt")
    (tmp_path / "x.xml").write_text("<a/>")
    with pytest.raises(InputError):
        read_player_boxes(tmp_path / "x.xml")


def test_add_frame_drops_bad_boxes_and_scales():
    boxes = PlayerBoxes(source="s", kind="detector", image_size=(960, 540))
    boxes.add_frame(0, "000001", [[10, 20, 30, 80], [np.nan, 0, 1, 1], [5, 5, 5, 9]])
    assert len(boxes.frames[0]) == 1 and len(boxes.issues) == 2
    scaled = boxes.scaled(1920, 1080)
    np.testing.assert_allclose(scaled.frames[0].boxes_px[0], [20, 40, 60, 160])
