"""Centre-circle hypotheses: the circle's image conic and the halfway line give the camera's homography."""

from __future__ import annotations

import math

import numpy as np

from broadtrack_graph.detect.marking_ellipses import ImageEllipse
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.court_circle import circle_line_homographies, ellipse_conic_n, pitch_circle_chords
from broadtrack_graph.reinit.court_lines import cameras_from_homographies

PITCH = PitchTemplate()
W, H = 1280, 720
RADIUS = 9.15
CENTRE = pitch_circle_chords(PITCH)[0]


def _centre_view() -> Camera:
    return Camera.from_degrees(1500.0, 0.0, 4.0, 74.0, 0.2, (3.0, 56.0, -16.0), W, H)


def _image_ellipse(camera: Camera) -> ImageEllipse:
    """The exact image of the centre circle (no distortion) as the map's ellipse finder returns it."""
    K = np.array([[camera.focal_px, 0, W / 2], [0, camera.focal_px, H / 2], [0, 0, 1.0]])
    R, t = camera.R_cw, -camera.R_cw @ camera.position_m
    H_px = K @ np.column_stack([R[:, 0], R[:, 1], t])
    Hinv = np.linalg.inv(H_px)
    conic = Hinv.T @ np.diag([1.0, 1.0, -RADIUS**2]) @ Hinv
    centre = np.linalg.solve(conic[:2, :2], -conic[:2, 2])
    value = centre @ conic[:2, :2] @ centre + 2 * conic[:2, 2] @ centre + conic[2, 2]
    eigenvalues, vectors = np.linalg.eigh(conic[:2, :2] / -value)
    a, b = 1 / math.sqrt(eigenvalues[0]), 1 / math.sqrt(eigenvalues[1])
    major = vectors[:, 0]
    return ImageEllipse(centre, (a, b), math.atan2(major[1], major[0]), 1000.0)


def _halfway_line_n(camera: Camera) -> np.ndarray:
    (u0, u1), _ = camera.project(np.array([[0.0, -8.0, 0.0], [0.0, 8.0, 0.0]]))
    line = np.cross(np.append((u0 - [W / 2, H / 2]) / (W / 2), 1.0), np.append((u1 - [W / 2, H / 2]) / (W / 2), 1.0))
    return line / np.linalg.norm(line[:2])


def test_the_ellipse_conic_holds_the_circles_image():
    truth = _centre_view()
    ellipse = _image_ellipse(truth)
    E = ellipse_conic_n(ellipse, (W, H))
    angles = np.linspace(0, 2 * math.pi, 12, endpoint=False)
    uv, _ = truth.project(np.column_stack([RADIUS * np.cos(angles), RADIUS * np.sin(angles), np.zeros(12)]))
    x = np.column_stack([(uv - [W / 2, H / 2]) / (W / 2), np.ones(12)])
    assert np.allclose(np.einsum("ki,ij,kj->k", x, E, x), 0.0, atol=1e-9)


def test_a_hypothesis_of_the_circle_and_the_halfway_line_is_the_true_camera():
    truth = _centre_view()
    H_n = circle_line_homographies([_image_ellipse(truth)], _halfway_line_n(truth)[None], (W, H), [CENTRE])
    cameras = cameras_from_homographies(H_n, (W, H), PITCH)
    assert len(cameras) >= 1
    gap = np.linalg.norm(cameras.C_w - truth.position_m, axis=1)
    k = int(np.argmin(gap))
    assert gap[k] < 0.5  # the centre spot's image is tried on a grid along the chord
    assert abs(cameras.focal_n[k] * W / 2 - truth.focal_px) < 0.03 * truth.focal_px


def test_a_line_far_from_the_ellipse_centre_makes_no_hypothesis():
    truth = _centre_view()
    far = _halfway_line_n(truth) + np.array([0.0, 0.0, 0.5])
    assert len(circle_line_homographies([_image_ellipse(truth)], far[None], (W, H), [CENTRE])) == 0


def test_a_penalty_arc_and_its_16m_line_give_the_camera():
    truth = Camera.from_degrees(1800.0, 0.0, -70.0, 66.0, 0.3, (70.0, 45.0, -20.0), W, H)  # near the right corner
    arc = pitch_circle_chords(PITCH)[1]
    assert arc.name == "right penalty arc"
    ellipse = _image_ellipse(truth.replace(position_m=truth.position_m - np.array([arc.centre_x_m, 0.0, 0.0])))
    (u0, u1), _ = truth.project(np.array([[arc.chord_x_m, -5.0, 0.0], [arc.chord_x_m, 5.0, 0.0]]))
    line = np.cross(np.append((u0 - [W / 2, H / 2]) / (W / 2), 1.0), np.append((u1 - [W / 2, H / 2]) / (W / 2), 1.0))
    H_n = circle_line_homographies([ellipse], (line / np.linalg.norm(line[:2]))[None], (W, H), [arc])
    cameras = cameras_from_homographies(H_n, (W, H), PITCH)
    gap = np.linalg.norm(cameras.C_w - truth.position_m, axis=1)
    assert len(cameras) and gap.min() < 0.5


def test_the_centre_circle_and_a_touchline_give_the_camera_without_the_halfway_line():
    from broadtrack_graph.reinit.court_circle import circle_pole_homographies

    truth = _centre_view()
    (u0, u1), _ = truth.project(np.array([[-20.0, -34.0, 0.0], [20.0, -34.0, 0.0]]))  # the far touchline
    line = np.cross(np.append((u0 - [W / 2, H / 2]) / (W / 2), 1.0), np.append((u1 - [W / 2, H / 2]) / (W / 2), 1.0))
    H_n = circle_pole_homographies([_image_ellipse(truth)], (line / np.linalg.norm(line[:2]))[None], (W, H), RADIUS,
                                   34.0)
    cameras = cameras_from_homographies(H_n, (W, H), PITCH)
    gap = np.linalg.norm(cameras.C_w - truth.position_m, axis=1)
    assert len(cameras) and gap.min() < 0.5


def test_four_correspondences_give_the_camera_s_homography_and_three_on_a_line_none():
    from broadtrack_graph.reinit.court_circle import _homographies_from_points

    camera = _centre_view()
    K = np.array([[camera.focal_px, 0, W / 2], [0, camera.focal_px, H / 2], [0, 0, 1.0]])
    R, t = camera.R_cw, -camera.R_cw @ camera.position_m
    truth = K @ np.column_stack([R[:, 0], R[:, 1], t])
    world = np.array([[[0.0, 9.15], [0.0, -9.15], [9.15, 0.0], [-9.15, 0.0]],
                      [[0.0, 0.0], [10.0, 0.0], [20.0, 0.0], [5.0, 5.0]]])  # the second: three on one line
    image = np.einsum("ij,kmj->kmi", truth, np.concatenate([world, np.ones((2, 4, 1))], axis=2))
    found = _homographies_from_points(image * 3.0, world)  # any scale of the image points
    expected = truth / np.linalg.norm(truth)
    assert np.allclose(found[0] * np.sign(found[0, 2, 2] * expected[2, 2]), expected, atol=1e-9)
    assert np.isnan(found[1]).all()
