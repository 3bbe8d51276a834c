import numpy as np

from broadtrack_graph.detect.player_ids import box_iou, link_track_ids
from broadtrack_graph.types.player_boxes import PlayerBoxes


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


def test_linker_frame_by_frame_gives_the_ids_of_linking_at_the_end():
    from broadtrack_graph.detect.player_ids import TrackIdLinker

    rng = np.random.default_rng(4)
    boxes = PlayerBoxes(source="detector", kind="detector")
    for k in [0, 1, 2, 4, 5, 6, 7]:  # a gap of two frames ends every track
        start = rng.uniform(0, 900, size=(6, 2))
        rows = np.column_stack([start + 3 * k, start + 3 * k + [20, 60]])
        boxes.add_frame(k, f"{k + 1:06d}", rows[rng.permutation(6)[: rng.integers(3, 7)]])
    at_the_end = link_track_ids(boxes)
    linker = TrackIdLinker()
    as_they_come = [linker.link(frame) for frame in boxes.frames]
    assert [f.track_ids.tolist() for f in as_they_come] == [f.track_ids.tolist() for f in at_the_end.frames]
    assert min(as_they_come[0].track_ids) == 0 and linker.next_id > 6
    # the gap (frame 2 -> 4) starts new ids only
    assert not set(as_they_come[3].track_ids) & set(np.concatenate([f.track_ids for f in as_they_come[:3]]))
