import json

import numpy as np
import pytest

from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.io.detections import annotations_to_observations, read_detections
from broadtrack_graph.io.detections_writer import DetectionsWriter
from broadtrack_graph.types.observations import FrameObservations, KeypointObservations


def test_round_trip_through_writer(tmp_path):
    pitch = PitchTemplate()
    keypoints = KeypointObservations(
        uv_px=np.array([[100.0, 200.0], [300.5, 400.25]]),
        points_w=np.array([pitch.keypoints["Centre spot"], [11.0, -20.16, 0.0]]),
        confidence=np.array([0.9, 0.8]),
        names=["Centre spot", ""],
    )
    frame = FrameObservations(3, 1920, 1080, lines_px={"Side line top": np.array([[10.0, 20.0], [30.0, 25.0]])},
                              keypoints=keypoints, player_boxes_px=np.array([[1, 2, 30, 80.0]]))
    path = tmp_path / "det.jsonl"
    with DetectionsWriter(path) as writer:
        writer.write(frame, frame_id="000004")
    read = read_detections(path)
    assert read.issues == [] and read.image_size == (1920, 1080) and read.frame_ids == {3: "000004"}
    back = read.frames[3]
    np.testing.assert_allclose(back.lines_px["Side line top"], frame.lines_px["Side line top"])
    np.testing.assert_allclose(back.keypoints.uv_px, keypoints.uv_px)
    np.testing.assert_allclose(back.keypoints.points_w, keypoints.points_w)
    np.testing.assert_allclose(back.player_boxes_px, frame.player_boxes_px)


def test_bad_items_are_reported_and_skipped_never_fatal(tmp_path):
    records = [
        {"frame": 0, "image_size": [100, 50], "units": "normalized",
         "lines": {"Middle line": [[0.5, 0.5], {"x": 0.5, "y": 0.25}], "Penalty spot": [[0.1, 0.1]],
                   "Side line top ": [[0.2, 0.1], [float("nan"), 0.1], [1.5, 0.1]]},
         "keypoints": [
             {"name": "Centre spot", "xy": [0.5, 0.5], "confidence": 0.9},
             {"name": "Centre spot", "xy": [0.51, 0.5], "confidence": 0.8},
             {"name": "Nowhere", "xy": [0.2, 0.2]},
             {"world": [1, 2, 0], "xy": [0.2, 0.2], "confidence": 0.1},
             {"world": [1, 2, 0], "xy": [2.0, 0.2]},
             {"world": [1, 2, 0], "xy": [float("nan"), 0.2]},
         ]},
        {"frame": 2, "lines": {"Middle line": [[10, 10]]}},
    ]
    text = "\n".join(json.dumps(r) for r in records) + "\nnot json\n" + '{"frame": 5, "lines": {"Middle l'
    path = tmp_path / "det.jsonl"
    path.write_text(text)
    read = read_detections(path)
    assert sorted(read.frames) == [0, 2]
    frame0 = read.frames[0]
    np.testing.assert_allclose(frame0.lines_px["Middle line"], [[49.5, 12.25], [49.5, 24.5]])
    np.testing.assert_allclose(frame0.lines_px["Side line top"], [[19.8, 4.9]])
    assert len(frame0.keypoints) == 1 and frame0.keypoints.names == ["Centre spot"]
    assert read.frames[2].width_px == 100  # size inherited from the first record
    joined = "\n".join(read.issues)
    for fragment in ["unknown line class 'Penalty spot'", "non-finite", "outside the image", "duplicate",
                     "unknown keypoint name 'Nowhere'", "below 0.30", "outside the 100x50 image",
                     ":3: malformed JSON", ":4: truncated last line"]:
        assert fragment in joined, fragment


def test_missing_or_empty_file_is_an_error(tmp_path):
    with pytest.raises(InputError, match="not found"):
        read_detections(tmp_path / "none.jsonl")
    (tmp_path / "empty.jsonl").write_text("")
    with pytest.raises(InputError, match="empty file"):
        read_detections(tmp_path / "empty.jsonl")


def test_annotation_import_uses_soccernet_pixel_rule():
    obs = annotations_to_observations({"Middle line": np.array([[0.5, 1.0]]), "Line unknown": np.array([[0, 0]])},
                                      7, 1920, 1080)
    np.testing.assert_allclose(obs.lines_px["Middle line"], [[959.5, 1079.0]])
    assert "Line unknown" not in obs.lines_px and obs.frame_index == 7


def test_all_unknown_class_names_is_one_error_not_hundreds_of_warnings(tmp_path):
    path = tmp_path / "det.jsonl"
    path.write_text("".join(json.dumps({"frame": i, "image_size": [100, 50], "lines": {"Foo": [[1, 2], [3, 4]]}}) + "\n"
                            for i in range(260)), encoding="utf-8")
    with pytest.raises(InputError, match="line class names such as 'Foo' are not SoccerNet classes"):
        read_detections(path)


def test_many_issues_are_summed_up(tmp_path, caplog):
    import logging

    path = tmp_path / "det.jsonl"
    path.write_text("".join(json.dumps({"frame": i, "image_size": [100, 50],
                                        "lines": {"Foo": [[1, 2]], "Middle line": [[10, 10], [10, 40]]}}) + "\n"
                            for i in range(60)), encoding="utf-8")
    with caplog.at_level(logging.WARNING):
        result = read_detections(path)
    assert len(result.issues) == 60 and len(caplog.records) == 11
    assert "50 more issues (50 x 'unknown line class')" in caplog.records[-1].getMessage()


def test_frame_range_reads_only_a_window_and_the_range_is_found_without_parsing(tmp_path):
    from broadtrack_graph.io.detections import detections_frame_range
    from broadtrack_graph.synth.detections_file import write_synthetic_detections

    path = write_synthetic_detections(tmp_path / "d.jsonl", 10, seed=1)
    assert detections_frame_range(path) == (0, 10)
    window = read_detections(path, frame_range=(3, 6))
    assert sorted(window.frames) == [3, 4, 5]
    whole = read_detections(path)
    assert window.frames[4].lines_px.keys() == whole.frames[4].lines_px.keys()
    assert all(np.array_equal(window.frames[4].lines_px[k], whole.frames[4].lines_px[k]) for k in whole.frames[4].lines_px)
    assert sorted(read_detections(path, frame_range=(8, None)).frames) == [8, 9]
