"""``bench placements --annotations DIR``: the court model on annotated markings."""

from __future__ import annotations

import json

import numpy as np

from broadtrack_graph.benchmarks.annotated_views import annotated_determinability, annotation_marking_map
from broadtrack_graph.cli import main
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import distances_to_polyline, project_template_polylines
from broadtrack_graph.io.annotations import write_annotation_file

W, H = 960, 540
PITCH = PitchTemplate()


def box_view() -> Camera:
    """The main camera zoomed on the right penalty area (the box, its arc, the goal line and the near touchline)."""
    return Camera.from_degrees(2200.0, 0.0, 20.0, 76.0, 0.0, (0.0, 58.0, -14.0), W, H)


def annotation_of(camera: Camera, every: int = 6) -> dict:
    """Every projected class annotated with every ``every``-th point of its projection, normalised."""
    polylines = project_template_polylines(camera, W, H)
    return {name: poly[::every] / np.array([W - 1, H - 1]) for name, poly in polylines.items()
            if len(poly[::every]) >= 2}


def test_the_map_draws_each_ground_polyline_one_pixel_wide_with_points_along_it():
    camera = box_view()
    ground = annotation_of(camera)
    lines = dict(ground, **{"Goal right post left": _straight(20, 20, 20, 200)})  # a post: annotated, not drawn
    marking_map, points = annotation_marking_map(lines, W, H, PITCH)
    assert marking_map.shape == (H, W) and marking_map.dtype == bool
    without_post, same_points = annotation_marking_map(ground, W, H, PITCH)
    assert np.array_equal(marking_map, without_post) and np.array_equal(points, same_points)
    polylines = [p * [W - 1, H - 1] for p in ground.values()]
    assert all(PITCH.is_on_ground(name) for name in ground) and len(polylines) >= 6
    length = sum(float(np.linalg.norm(np.diff(p, axis=0), axis=1).sum()) for p in polylines)
    segments = sum(len(p) - 1 for p in polylines)
    assert length - segments <= len(points) <= length + segments  # a point every pixel along
    nearest = np.min([distances_to_polyline(points, p) for p in polylines], axis=0)
    assert nearest.max() < 1e-6
    rows, cols = np.nonzero(marking_map)
    drawn = np.column_stack([cols, rows]).astype(float)
    on = np.min([distances_to_polyline(drawn, p) for p in polylines], axis=0)
    assert on.max() <= 1.1  # one pixel wide: no drawn pixel much further than a pixel from a polyline
    assert len(drawn) < 1.5 * length


def _straight(x0, y0, x1, y1):
    return np.array([[x0, y0], [x1, y1]], float) / [W - 1, H - 1]


def test_two_lines_of_each_direction_or_a_circle_and_a_line_determine_a_camera():
    two_and_two = {"Side line top": _straight(0, 100, 900, 90), "Big rect. right top": _straight(500, 200, 900, 190),
                   "Side line right": _straight(900, 90, 950, 300),
                   "Big rect. right main": _straight(500, 200, 600, 500)}
    assert annotated_determinability(two_and_two, W, H, PITCH) == (
        True, {"x_lines": 2, "y_lines": 2, "curves": []})
    # The two boxes' tops on one side lie on one pitch line: one line, however many classes.
    one_line_twice = dict(two_and_two, **{"Big rect. left top": _straight(0, 210, 300, 205)})
    assert annotated_determinability(one_line_twice, W, H, PITCH)[1]["x_lines"] == 2
    short = dict(two_and_two, **{"Big rect. right main": _straight(500, 200, 510, 230)})  # 32 px: does not count
    assert annotated_determinability(short, W, H, PITCH) == (
        False, {"x_lines": 2, "y_lines": 1, "curves": []})
    arc = np.column_stack([np.linspace(400, 600, 9), 300 + 40 * np.sin(np.linspace(0, np.pi, 9))]) / [W - 1, H - 1]
    circle_and_line = {"Circle right": arc, "Big rect. right main": _straight(500, 200, 600, 500)}
    assert annotated_determinability(circle_and_line, W, H, PITCH) == (
        True, {"x_lines": 0, "y_lines": 1, "curves": ["Circle right"]})
    assert not annotated_determinability({"Circle right": arc}, W, H, PITCH)[0]


def test_the_court_model_finds_the_camera_of_an_annotated_box_view(tmp_path):
    folder = tmp_path / "annotations"
    folder.mkdir()
    write_annotation_file(folder / "00001.json", annotation_of(box_view()))
    write_annotation_file(folder / "00002.json", {"Side line top": _straight(0, 100, 900, 90)})  # one line: apart
    out = tmp_path / "report.json"
    assert main(["bench", "placements", "--annotations", str(folder), "--width", str(W), "--height", str(H),
                 "--no-progress", "--json", str(out)]) == 0
    report = json.loads(out.read_text(encoding="utf-8"))
    assert report["frames_read"] == 2 and report["determinable"] == 1
    box, line = report["frames"]
    assert box["outcome"] == "found" and box["error_px"] < 1.0 and box["confidence"] >= box["written_at"]
    assert report["counts"] == {"found": 1, "near": 0, "wrong": 0, "none": 0}
    assert not line["determinable"] and line["outcome"] == "none"
    assert report["seconds"]["median"] is not None


def test_a_missing_folder_is_one_line_naming_it(tmp_path, capsys):
    assert main(["bench", "placements", "--annotations", str(tmp_path / "nowhere"), "--no-progress"]) != 0
    error = capsys.readouterr().err.strip().splitlines()
    assert len(error) == 1 and "nowhere" in error[0]


def test_real_broadcast_views_from_their_annotations(sn_calibration_dir, tmp_path):
    """Two real SoccerNet frames (a wide main-camera view, a view of a penalty area): found."""
    out = tmp_path / "report.json"
    assert main(["bench", "placements", "--annotations", str(sn_calibration_dir / "annotations"), "--width", str(W),
                 "--height", str(H), "--limit", "2", "--no-progress", "--json", str(out)]) == 0
    report = json.loads(out.read_text(encoding="utf-8"))
    assert [row["frame"] for row in report["frames"]] == ["00002", "00004"]
    assert report["counts"]["found"] == 2
    assert all(row["error_px"] < 3.0 for row in report["frames"])
