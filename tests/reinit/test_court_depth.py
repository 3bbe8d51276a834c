"""Cameras along a camera's line of sight: the point looked at stays put, its surroundings keep their size."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.reinit.court_depth import along_line_of_sight

W, H = 1280, 720


def _camera(position, pan_deg=20.0, tilt_deg=75.0) -> Camera:
    return Camera(3000.0, 0.01, math.radians(pan_deg), math.radians(tilt_deg), 0.01, np.asarray(position, float), W, H)


def test_the_ground_point_looked_at_stays_at_the_image_centre_and_its_surroundings_keep_their_size():
    camera = _camera((-10.0, 60.0, -20.0))
    axis = camera.optical_axis_w
    look_at = camera.position_m + (-camera.position_m[2] / axis[2]) * axis
    near = look_at + np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
    uv0, _ = camera.project(near)
    moved = along_line_of_sight(camera, [0.5, 1.0, 2.0])
    assert len(moved) == 3
    for factor, other in zip([0.5, 1.0, 2.0], moved):
        uv, ok = other.project(near)
        assert ok.all()
        np.testing.assert_allclose(uv[0], camera.principal_point, atol=1e-6)
        # a metre on the ground beside it: the same length in the image within a few per cent (perspective changes)
        np.testing.assert_allclose(np.linalg.norm(uv[1:] - uv[:1], axis=1), np.linalg.norm(uv0[1:] - uv0[:1], axis=1),
                                   rtol=0.05)
        np.testing.assert_allclose(other.focal_px, factor * camera.focal_px)
        np.testing.assert_allclose(np.linalg.norm(other.position_m - look_at),
                                   factor * np.linalg.norm(camera.position_m - look_at))
        assert (other.pan_rad, other.tilt_rad, other.roll_rad, other.k1) == \
            (camera.pan_rad, camera.tilt_rad, camera.roll_rad, camera.k1)


def test_a_view_above_the_horizon_has_no_line_of_sight_to_walk():
    assert along_line_of_sight(_camera((0.0, 60.0, -20.0), tilt_deg=95.0), [0.5, 2.0]) == []


def _annotated_box_view_map(camera: Camera):
    """The marking map and points of a view's ground markings, drawn one pixel wide from their projections."""
    from broadtrack_graph.benchmarks.annotated_views import annotation_marking_map
    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.geometry.template import project_template_polylines

    w, h = camera.width_px, camera.height_px
    lines = {name: poly / np.array([w - 1, h - 1]) for name, poly in project_template_polylines(camera, w, h).items()}
    return annotation_marking_map(lines, w, h, PitchTemplate())


def test_the_court_model_walks_only_a_narrow_view_under_its_bar_along_its_line_of_sight(monkeypatch):
    """The court model's camera of a narrow view (f at least ``narrow_view_focal_per_width`` of the width) under
    ``narrow_view_walk_below`` is fitted again from starts along its line of sight; a wide or confident one is not."""
    import broadtrack_graph.reinit.court as court
    from broadtrack_graph.geometry.template import fitting_curves
    from broadtrack_graph.reinit.court_config import CourtConfig

    asked = []
    walk = court.most_confident_along_line_of_sight

    def recorded(camera, points_px, curves, search, factors, confidence_of):
        asked.append((camera.focal_px, tuple(factors)))
        return walk(camera, points_px, curves, search, factors, confidence_of)

    monkeypatch.setattr(court, "most_confident_along_line_of_sight", recorded)
    box = Camera.from_degrees(2200.0, 0.0, 20.0, 76.0, 0.0, (0.0, 58.0, -14.0), 960, 540)  # 25 deg across
    marking_map, points = _annotated_box_view_map(box)
    curves = fitting_curves()
    config = CourtConfig()
    found = court.reinit_from_court(marking_map, points, (960, 540), curves=curves, config=config)
    assert found.camera is not None and found.score.jaccard >= config.narrow_view_walk_below
    assert asked == []  # confident: not walked
    always = CourtConfig(narrow_view_walk_below=1.01)
    walked = court.reinit_from_court(marking_map, points, (960, 540), curves=curves, config=always)
    assert len(asked) == 1 and asked[0][1] == always.narrow_view_depth_factors
    assert asked[0][0] >= always.narrow_view_focal_per_width * 960
    assert walked.camera is not None and walked.score.jaccard >= found.score.jaccard - 1e-9
    asked.clear()
    court.reinit_from_court(marking_map, points, (960, 540), curves=curves,
                            config=CourtConfig(narrow_view_walk_below=1.01, narrow_view_focal_per_width=3.0))
    assert asked == []  # 2200 px at 960 wide is not narrow at 3 widths


def test_a_real_box_view_fitted_off_along_its_line_of_sight_is_walked_onto_its_markings(sn_calibration_dir):
    """SoccerNet frame 01627 (a main camera zoomed on the left penalty area, about 15 deg across): from its annotated
    markings the court model's fit, without the arcs' hypotheses (:mod:`broadtrack_graph.reinit.court_arcs`,
    :mod:`broadtrack_graph.reinit.court_arc_corners`), stops
    12.7 px (median) off them at 0.83; walked along its line of sight, 0.8 px. With them (the default) its penalty arc
    and 16.5 m line give a camera within 2 px before any walk."""
    from broadtrack_graph.benchmarks.annotated_views import annotation_marking_map
    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.geometry.template import fitting_curves
    from broadtrack_graph.io.annotations import read_annotation_file
    from broadtrack_graph.metrics.soccernet import evaluate_frame
    from broadtrack_graph.reinit.court import reinit_from_court
    from broadtrack_graph.reinit.court_arc_corners import ArcCornerConfig
    from broadtrack_graph.reinit.court_arcs import CourtArcConfig
    from broadtrack_graph.reinit.court_config import CourtConfig

    pitch = PitchTemplate()
    lines = {name: points for name, points in read_annotation_file(sn_calibration_dir / "annotations" / "01627.json")
             .items() if pitch.is_on_ground(name)}
    marking_map, points = annotation_marking_map(lines, 960, 540, pitch)
    curves = fitting_curves(pitch)

    def error_px(result):
        return float(np.median(evaluate_frame(lines, result.camera, 960, 540, (5.0,)).all_distances(5.0)))

    no_arcs = CourtConfig(arc=CourtArcConfig(max_pairings=0), arc_corner=ArcCornerConfig(max_pairings=0))
    unwalked = reinit_from_court(marking_map, points, (960, 540), pitch, curves,
                                 config=replace(no_arcs, narrow_view_depth_factors=()))
    walked = reinit_from_court(marking_map, points, (960, 540), pitch, curves, config=no_arcs)
    assert error_px(unwalked) > 10.0 and unwalked.score.jaccard < 0.9
    assert error_px(walked) < 2.0 and walked.score.jaccard > unwalked.score.jaccard
    assert error_px(reinit_from_court(marking_map, points, (960, 540), pitch, curves)) < 2.0
