import json

import numpy as np

from broadtrack_graph.io.gamestate_players import read_gamestate_players


def _annotation(image_id, track_id, box, role="player", team="left"):
    x, y, w, h = box
    return {"id": f"{image_id}-{track_id}", "image_id": image_id, "track_id": track_id, "supercategory": "object",
            "category_id": 1, "attributes": {"role": role, "team": team, "jersey": None},
            "bbox_image": {"x": x, "y": y, "w": w, "h": h}}


def test_reads_players_skips_ball_and_bad_entries(tmp_path):
    data = {
        "images": [{"image_id": "1060000001", "file_name": "000001.jpg", "width": 1920, "height": 1080},
                   {"image_id": "1060000002", "file_name": "000002.jpg", "width": 1920, "height": 1080}],
        "annotations": [
            {"id": "p", "image_id": "1060000001", "supercategory": "pitch", "lines": {}},
            _annotation("1060000001", 7, (100, 200, 20, 60)),
            _annotation("1060000001", 8, (300, 200, 20, 60), role="referee", team=None),
            _annotation("1060000001", 99, (500, 500, 8, 8), role="ball", team=None),
            _annotation("1060000002", 7, (102, 201, 20, 60)),
            _annotation("1060000002", 9, (float("nan"), 1, 2, 3)),
            _annotation("1060000009", 9, (1, 1, 2, 3)),
            {"id": "nobox", "image_id": "1060000002", "supercategory": "object", "track_id": 3},
        ],
    }
    path = tmp_path / "Labels-GameState.json"
    path.write_text(json.dumps(data))
    boxes = read_gamestate_players(path)
    assert boxes.kind == "gamestate" and boxes.image_size == (1920, 1080)
    assert [(f.frame_index, f.frame_id) for f in boxes.frames] == [(0, "000001"), (1, "000002")]
    first = boxes.frames[0]
    np.testing.assert_array_equal(first.track_ids, [7, 8])
    assert first.roles == ["player", "referee"] and first.teams == ["left", None]
    np.testing.assert_allclose(first.boxes_px[0], [100, 200, 120, 260])
    assert boxes.image_ids == {"000001": "1060000001", "000002": "1060000002"}
    assert len(boxes.issues) == 3  # NaN box, unknown image, no bbox_image
