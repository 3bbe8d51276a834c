"""Template projection: SoccerNet's polylines (sampling, border points), point-to-polyline distances, dense curves."""

from __future__ import annotations

import pickle

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import LINE_CLASSES, PitchTemplate
from broadtrack_graph.geometry.template import (
    SOCCERNET_CIRCLE_STEP_M,
    SOCCERNET_LINE_STEP_M,
    TemplateCurves,
    TemplateSampling,
    _border_point,
    _project_like_official,
    closest_on_polyline,
    distances_to_polyline,
    finite_runs,
    project_template,
    project_template_polylines,
)

W, H = 960, 540


def camera_main(**changes):
    camera = Camera.from_degrees(1100.0, 0.0, -20.0, 72.0, 0.0, (0.0, 55.0, -14.0), W, H)
    return camera.replace(**changes) if changes else camera


def on_border(points: np.ndarray) -> np.ndarray:
    return (np.isclose(points[:, 0], 0, atol=1e-9) | np.isclose(points[:, 0], W - 1, atol=1e-9)
            | np.isclose(points[:, 1], 0, atol=1e-9) | np.isclose(points[:, 1], H - 1, atol=1e-9))


def test_distance_to_polyline():
    poly = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0]])
    d = distances_to_polyline(np.array([[5.0, 3.0], [-3.0, -4.0], [12.0, 5.0], [10.0, 10.0]]), poly)
    np.testing.assert_allclose(d, [3.0, 5.0, 2.0, 0.0])
    np.testing.assert_allclose(distances_to_polyline(np.array([[3.0, 4.0]]), np.array([[0.0, 0.0]])), [5.0])


def test_distance_to_polyline_by_hand_with_a_repeated_vertex():
    # Segments (0,0)-(0,0) (zero length) and (0,0)-(3,4) (length 5, direction (0.6, 0.8)).
    poly = np.array([[0.0, 0.0], [0.0, 0.0], [3.0, 4.0]])
    points = np.array([[4.0, -3.0], [6.0, 8.0], [-1.0, 0.0], [1.5, 2.0]])
    # (4,-3) is perpendicular to the segment at its start: 5; (6,8) lies beyond its end (3,4): |(3,4)| = 5;
    # (-1,0) projects before the start: 1; (1.5,2) is on the segment: 0.
    np.testing.assert_allclose(distances_to_polyline(points, poly), [5.0, 5.0, 1.0, 0.0], atol=1e-12)


def test_closest_on_polyline_respects_the_segment_mask():
    poly = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0]])
    points = np.array([[4.0, 1.0], [12.0, 5.0]])
    seg, t, d = closest_on_polyline(points, poly, np.array([True, True]))
    assert seg.tolist() == [0, 1]
    np.testing.assert_allclose(t, [0.4, 0.5])
    np.testing.assert_allclose(d, [1.0, 2.0])
    # Without the first segment, (4, 1) goes to (10, 1) on the second one: t = 0.1, 6 px away.
    seg, t, d = closest_on_polyline(points[:1], poly, np.array([False, True]))
    assert seg.tolist() == [1]
    np.testing.assert_allclose(t, [0.1])
    np.testing.assert_allclose(d, [6.0])


def test_border_point_by_hand():
    # Leaving through the left border: line y = 50 meets x = 0 and x = W - 1; the nearest to (-10, 50) wins.
    assert _border_point(np.array([-10.0, 50.0]), np.array([10.0, 50.0]), W, H) == (0.0, 50.0)
    # Leaving along y = x / 2: it meets x = W - 1 at y = (W - 1) / 2 inside the image (and y = H - 1 only
    # at x = 1078, outside), and (0, 0) is further from the current point.
    hit = _border_point(np.array([1200.0, 600.0]), np.array([800.0, 400.0]), W, H)
    assert hit == pytest.approx((W - 1.0, (W - 1.0) / 2.0))
    # A line that never crosses the image has no border point.
    assert _border_point(np.array([-10.0, -10.0]), np.array([-20.0, -5.0]), W, H) is None


def test_border_points_lie_on_the_image_border():
    camera = camera_main()
    sampling = TemplateSampling()
    uv, front = _project_like_official(camera, sampling.points_w)
    polylines = project_template_polylines(camera, W, H, sampling)
    added = 0
    for index, name in enumerate(sampling.class_names):
        if name not in polylines:
            continue
        start, stop = sampling.offsets[index], sampling.offsets[index + 1]
        uv_class, front_class = uv[start:stop], front[start:stop]
        inside = front_class & (uv_class[:, 0] >= 0) & (uv_class[:, 0] < W) & (uv_class[:, 1] >= 0) & (uv_class[:, 1] < H)
        poly = polylines[name]
        # Every point of the polyline is a projected inside sample or a border point.
        is_sample = (np.abs(poly[:, None, :] - uv_class[inside][None]).max(axis=2) == 0).any(axis=1)
        assert np.all(on_border(poly[~is_sample])), name
        assert np.all((poly[:, 0] >= 0) & (poly[:, 0] < W) & (poly[:, 1] >= 0) & (poly[:, 1] < H))
        # The inside samples come in their template order.
        np.testing.assert_array_equal(poly[is_sample], uv_class[inside])
        added += int((~is_sample).sum())
    assert added >= 2


def test_border_point_is_added_where_a_line_leaves_the_image():
    camera = camera_main()
    polylines = project_template_polylines(camera, W, H)
    touching = 0
    for poly in polylines.values():
        on_border = (np.isclose(poly[:, 0], 0) | np.isclose(poly[:, 0], W - 1) | np.isclose(poly[:, 1], 0)
                     | np.isclose(poly[:, 1], H - 1))
        touching += int(on_border.any())
        assert np.all((poly[:, 0] >= 0) & (poly[:, 0] < W) & (poly[:, 1] >= 0) & (poly[:, 1] < H))
    assert touching >= 2
    # An annotated point exactly at the image border is matched thanks to the border point.
    name = next(n for n, p in polylines.items() if np.isclose(p[0, 0], 0) or np.isclose(p[-1, 0], 0))
    poly = polylines[name]
    end = poly[0] if np.isclose(poly[0, 0], 0) else poly[-1]
    assert distances_to_polyline(end[None], poly)[0] == 0.0


def test_camera_looking_away_projects_nothing():
    sky = Camera.from_degrees(1100.0, 0.0, 180.0, 100.0, 0.0, (0.0, 55.0, -14.0), W, H)  # looks away, above horizon
    assert project_template_polylines(sky, W, H) == {}


def test_sampling_follows_the_official_steps():
    sampling = TemplateSampling()
    expected = PitchTemplate().sample_soccernet(SOCCERNET_LINE_STEP_M, SOCCERNET_CIRCLE_STEP_M)
    assert sampling.class_names == list(expected)
    for index, name in enumerate(sampling.class_names):
        np.testing.assert_array_equal(sampling.points_w[sampling.offsets[index]:sampling.offsets[index + 1]], expected[name])
    assert sampling.offsets[-1] == len(sampling.points_w)


def test_polylines_are_rescaled_to_the_evaluation_resolution():
    camera = camera_main(k1=-0.05)
    small = project_template_polylines(camera, W, H)
    large = project_template_polylines(camera.rescaled(2 * W, 2 * H), W, H)
    assert small.keys() == large.keys()
    for name in small:
        np.testing.assert_allclose(large[name], small[name], atol=1e-9)


def test_finite_runs():
    assert finite_runs(np.array([True, True, False, True, False, True, True, True])) == [(0, 2), (5, 8)]
    assert finite_runs(np.zeros(3, bool)) == []


def test_template_curves_sample_every_class_with_both_ends():
    pitch = PitchTemplate()
    curves = TemplateCurves(pitch, line_step_m=2.0, circle_step_m=0.5)
    assert set(curves.samples_w) == set(pitch.elements)
    middle = curves.samples_w["Middle line"]  # x = 0 from touchline to touchline, 68 m
    np.testing.assert_array_equal(middle[:, 0], 0.0)
    np.testing.assert_allclose(sorted(middle[[0, -1], 1]), [-34.0, 34.0])
    steps = np.linalg.norm(np.diff(middle, axis=0), axis=1)
    assert np.all(steps <= 2.0 + 1e-9) and len(middle) == 35


def test_template_curves_and_sampling_are_pickled_as_their_recipes():
    pitch = PitchTemplate()
    curves = TemplateCurves(pitch, line_step_m=1.0, circle_step_m=0.25)
    curves.stacked(list(curves.samples_w))  # a filled cache is not sent
    sampling = TemplateSampling(pitch)
    for template in (curves, sampling):
        assert len(pickle.dumps(template)) < 8000  # a worker process starts without waiting for its imports
    again = pickle.loads(pickle.dumps(curves))
    assert (again.line_step_m, again.circle_step_m) == (1.0, 0.25) and list(again.samples_w) == list(curves.samples_w)
    for name, samples in curves.samples_w.items():
        np.testing.assert_array_equal(again.samples_w[name], samples)
    again = pickle.loads(pickle.dumps(sampling))
    assert again.class_names == sampling.class_names
    np.testing.assert_array_equal(again.points_w, sampling.points_w)
    np.testing.assert_array_equal(again.offsets, sampling.offsets)


def test_project_template_is_dense_and_inside():
    camera = camera_main(k1=-0.05)
    curves = TemplateCurves()
    template = project_template(camera, curves, W, H, spacing_px=1.0)
    uv = template.uv_px
    assert len(uv) > 1000
    assert np.all((uv[:, 0] >= 0) & (uv[:, 0] <= W - 1) & (uv[:, 1] >= 0) & (uv[:, 1] <= H - 1))
    for j in np.unique(template.class_index):
        assert curves.pitch.is_on_ground(LINE_CLASSES[j])
        points = uv[template.class_index == j]
        # Consecutive dense samples of one class are at most about a pixel apart (runs may restart).
        gaps = np.linalg.norm(np.diff(points, axis=0), axis=1)
        assert np.median(gaps) <= 1.0 + 1e-9
    assert np.all(template.width_m_px > 0)


def test_project_template_samples_lie_on_each_class_curve_and_a_class_alone_gives_its_own_samples():
    camera = camera_main(k1=-0.05)
    curves = TemplateCurves(line_step_m=1.0, circle_step_m=0.5)
    template = project_template(camera, curves, W, H, spacing_px=1.0)
    for j in np.unique(template.class_index):
        name = LINE_CLASSES[j]
        alone = project_template(camera, curves, W, H, spacing_px=1.0, classes=[name])
        np.testing.assert_array_equal(alone.uv_px, template.uv_px[template.class_index == j])
        # Every dense sample lies on the class's projected polyline (densified between two projected samples).
        uv, front = camera.project(curves.samples_w[name])
        valid = front[:-1] & front[1:]
        _, _, distance = closest_on_polyline(alone.uv_px, uv, valid)
        assert distance.max() < 1e-6
    points, classes, joins = curves.stacked(["Middle line", "Circle central"])
    assert len(points) == len(curves.samples_w["Middle line"]) + len(curves.samples_w["Circle central"])
    assert joins.sum() == len(points) - 2  # one segment less per class
    assert curves.stacked(["Middle line", "Circle central"])[0] is points  # built once
    np.testing.assert_array_equal(np.unique(classes), sorted(LINE_CLASSES.index(n) for n in ("Middle line", "Circle central")))
