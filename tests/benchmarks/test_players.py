import numpy as np

from broadtrack_graph.benchmarks.players import camera_jitter_m, score_players
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.io.players_file import positions_from_lines
from broadtrack_graph.types.track_record import RunRecords, TrackRecord


def test_score_players_splits_by_distance_and_scores_distance_covered():
    camera = Camera.from_degrees(2000.0, 0.0, 0.0, 74.0, 0.0, [0.0, 55.0, -15.0], 1920, 1080)
    truth = {"fps": 25.0, "frames": {}}
    lines = []
    for k in range(60):
        fid = f"{k + 1:06d}"
        near, far = [0.2 * k, 10.0], [0.2 * k, -30.0]  # 45 m and 85 m from the camera
        truth["frames"][fid] = {"1": near, "2": far}
        for tid, xy, offset in ((1, near, 0.1), (2, far, -0.3)):
            lines.append({"frame": k, "frame_id": fid, "track_id": tid, "box_px": [0, 0, 1, 1],
                          "x_m": xy[0] + offset, "y_m": xy[1]})
    report = score_players(lines, truth, {fid: camera for fid in truth["frames"]}, 25.0)
    assert report["near_lt_60m"]["count"] == 60 and abs(report["near_lt_60m"]["median_m"] - 0.1) < 1e-6
    assert abs(report["far_ge_60m"]["median_m"] - 0.3) < 1e-6
    assert report["distance_smoothed"]["tracks"] == 2
    assert report["distance_smoothed"]["median_abs_rel_error_pct"] < 1e-6  # a constant offset moves no distance


def test_camera_jitter_is_zero_for_a_still_camera():
    camera = Camera.from_degrees(2000.0, 0.0, 0.0, 74.0, 0.0, [0.0, 55.0, -15.0], 1920, 1080)
    records = [TrackRecord(k, f"{k + 1:06d}", k / 25, camera) for k in range(4)]
    track = RunRecords(records, 1920, 1080, {}, None)
    positions = positions_from_lines([{"frame": k, "frame_id": f"{k + 1:06d}", "track_id": 1,
                                       "box_px": [900, 700, 920, 760], "x_m": 0.0, "y_m": 0.0} for k in range(4)])
    values = camera_jitter_m(track, positions)
    assert len(values) == 2 and np.allclose(values, 0.0)


def test_detector_boxes_are_scored_by_their_bottom_against_the_true_boxes(tmp_path):
    import cv2

    from broadtrack_graph.benchmarks.players import detector_box_bottoms
    from broadtrack_graph.types.player_boxes import PlayerBoxes

    (tmp_path / "img1").mkdir()
    boxes = PlayerBoxes()
    for k in range(2):
        image = np.zeros((360, 640, 3), np.uint8)
        image[:] = (40, 140, 50)
        cv2.rectangle(image, (300, 150), (310, 174), (30, 30, 200), -1)  # a body; its legs below
        for x in (302, 308):
            cv2.line(image, (x, 175), (x, 192), (200, 200, 200), 1)
        # a sensor's grain: a noiseless frame of one upright figure on flat grass reads as smeared along it
        # (detect.motion_blur), and the smear undone rings about the figure
        image = np.clip(image + np.random.default_rng(k).normal(0.0, 1.0, image.shape), 0, 255).astype(np.uint8)
        cv2.imwrite(str(tmp_path / "img1" / f"{k + 1:06d}.jpg"), image)
        boxes.add_frame(k, f"{k + 1:06d}", [[300.0, 150.0, 311.0, 193.0], [500.0, 100.0, 520.0, 160.0]])
    report = detector_box_bottoms(tmp_path, boxes, every=1)
    assert report["true_boxes"] == 4 and report["matched"] == 2  # the second true box has no player drawn
    assert abs(report["bottom_error_share_of_height"]["median"]) < 0.1
    assert report["bottom_error_share_of_height"]["within_10_pct"] == 1.0
