import numpy as np

from broadtrack_graph.detect.player_ids import box_iou, link_track_ids
from broadtrack_graph.io.player_boxes import PlayerBoxes


def test_iou():
    iou = box_iou(np.array([[0, 0, 10, 10]]), np.array([[0, 0, 10, 10], [5, 0, 15, 10], [20, 20, 30, 30]]))
    np.testing.assert_allclose(iou, [[1.0, 1 / 3, 0.0]])


def test_linking_follows_moving_boxes_and_starts_new_ids():
    boxes = PlayerBoxes(source="detector", kind="detector")
    for k in range(4):
        rows = [[100 + 2 * k, 100, 120 + 2 * k, 160], [400 - 2 * k, 100, 420 - 2 * k, 160]]
        if k == 2:
            rows.append([800, 500, 820, 560])
        boxes.add_frame(k, None, rows)
    linked = link_track_ids(boxes)
    ids = [f.track_ids.tolist() for f in linked.frames]
    assert ids[0] == ids[1] == ids[3] == ids[2][:2]
    assert ids[2][2] not in ids[0] and len(set(ids[0])) == 2
