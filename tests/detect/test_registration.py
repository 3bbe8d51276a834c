"""The predicted template registered on the ridge points before naming (detect.registration, WeightFreeDetector)."""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from broadtrack_graph.detect.detector import PredictedCamera
from broadtrack_graph.detect.registration import register_template
from broadtrack_graph.detect.weightfree import WeightFreeDetector
from broadtrack_graph.detect.weightfree_config import WeightFreeConfig
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves, distances_to_polyline, project_template

PITCH = PitchTemplate()
FINE = TemplateCurves(PITCH, line_step_m=0.1, circle_step_m=0.05)
W, H = 960, 540


def _camera() -> Camera:
    """A main camera on the halfway line, 12 m up, looking at the left half: the far touchline, the centre circle,
    the left box and its arc in view."""
    return Camera.from_degrees(1000.0, 0.0, -20.0, 72.0, 0.0, (0.0, 45.0, -12.0), W, H)


def _drawn(camera: Camera, name: str, shift_m=(0.0, 0.0)) -> np.ndarray:
    """(K, 2) pixels of a class drawn by the camera, inside the image (``shift_m``: moved on the ground first)."""
    uv, front = camera.project(FINE.samples_w[name] + np.array([shift_m[0], shift_m[1], 0.0]))
    return uv[front & camera.in_image(uv)]


def test_registration_recovers_a_turn_and_zoom_and_its_residual_scale():
    predicted = _camera()
    truth = Camera.from_degrees(1000.0 * 1.01, 0.0, -20.0 + 0.4, 72.0 - 0.3, 0.2, (0.0, 45.0, -12.0), W, H)
    template = project_template(predicted, FINE, W, H, 0.5)
    rng = np.random.default_rng(0)
    drawn = project_template(truth, FINE, W, H, 0.5).uv_px
    points = drawn[rng.choice(len(drawn), 800, replace=False)]
    points = points + rng.normal(0.0, 0.3, points.shape)
    clutter = rng.uniform([0, 0], [W, H], (150, 2))  # specks anywhere
    both = np.vstack([points, clutter])
    tree = cKDTree(template.uv_px)
    _, nearest = tree.query(both)  # each point named after its nearest sample
    result = register_template(template.uv_px, both, nearest, predicted.focal_px, predicted.principal_point, 0.5,
                               tree, 30.0)
    assert result is not None
    before, _ = cKDTree(drawn).query(template.uv_px)
    moved = result.apply(template.uv_px)
    after, _ = cKDTree(drawn).query(moved)
    inside = np.all((moved > 20) & (moved < [W - 20, H - 20]), axis=1)  # still in the true camera's view
    assert np.median(before) > 5.0 and np.percentile(after[inside], 99) < 0.5
    assert np.allclose(result.back(result.apply(template.uv_px)), template.uv_px, atol=1e-6)
    assert 0.15 < result.scale_px < 0.6  # the points' own noise (0.3 px a coordinate), not the clutter
    # Too few points near the template: no registration.
    assert register_template(template.uv_px, points[:10], nearest[:10], predicted.focal_px,
                             predicted.principal_point, 0.5) is None


def test_a_structure_beyond_the_touchline_is_not_named_after_a_marking_the_frame_does_not_show():
    """The far touchline is not in the frame; a bright edge 7 px beyond it is. A prediction 10 px off, unsure by
    12 px, names that edge as the touchline; the template registered on the points puts it off the pitch, and every
    marking that is there is named within a pixel of it."""
    truth = _camera()
    shown = ("Middle line", "Circle central", "Big rect. left main", "Big rect. left top", "Circle left")
    points = [_drawn(truth, name) for name in shown]
    edge = _drawn(truth, "Side line top") - np.array([0.0, 7.0])  # the boards' lower edge, beyond the touchline
    points.append(edge)
    points = np.vstack(points)
    predicted = PredictedCamera(truth.replace(pan_rad=truth.pan_rad + np.radians(0.5)), uncertainty_px=12.0)

    def named_by(register: bool) -> dict[str, np.ndarray]:
        detector = WeightFreeDetector(PITCH, WeightFreeConfig(register_template=register))
        return detector.name_points(points, predicted, 1.0, (W, H))

    def on_the_edge(named: dict[str, np.ndarray]) -> int:
        return int(sum((distances_to_polyline(p, edge) < 0.5).sum() for p in named.values()))

    assert on_the_edge(named_by(False)) > 100  # the failure registration is for
    named = named_by(True)
    assert on_the_edge(named) == 0
    assert set(shown) <= set(named)
    for name in shown:
        assert np.median(distances_to_polyline(named[name], _drawn(truth, name))) < 1.0


def test_points_on_the_outer_lines_are_named_and_those_beyond_them_are_not():
    truth = _camera()
    predicted = PredictedCamera(truth.replace(pan_rad=truth.pan_rad + np.radians(0.3), focal_px=truth.focal_px * 1.01),
                                uncertainty_px=12.0)
    inside = ("Middle line", "Circle central", "Big rect. left main", "Big rect. left top", "Circle left")
    outer = ("Side line top", "Side line left")
    beyond = (_drawn(truth, "Side line top", (0.0, -4.0)),  # 4 m beyond the far touchline (5-7 px): the boards
              _drawn(truth, "Side line left", (-2.0, 0.0)))  # 2 m behind the goal line (5-7 px)
    points = np.vstack([_drawn(truth, name) for name in inside + outer] + list(beyond))
    named = WeightFreeDetector(PITCH).name_points(points, predicted, 1.0, (W, H))
    assert set(inside + outer) <= set(named)
    for name in outer:  # the whole line, on it
        line = _drawn(truth, name)
        length_px = np.linalg.norm(np.diff(line, axis=0), axis=1).sum()
        assert len(named[name]) > 0.5 * length_px / 3.0  # cell means: one a 3 px cell
        assert np.median(distances_to_polyline(named[name], line)) < 1.0
    assert not any((distances_to_polyline(p, edge) < 0.5).any() for p in named.values() for edge in beyond)
