"""The tracker's 8-vector state: its names and order, its projection against Camera, the round trip."""

from __future__ import annotations

import math

import numpy as np

from broadtrack_graph.geometry.camera import Camera, angles_from_rotation, rotation_from_angles
from broadtrack_graph.geometry.distortion import unfolded_radius2
from broadtrack_graph.geometry.state import (
    ANGLES,
    BEHIND_CAMERA_Z,
    FOCAL,
    K1,
    PAN,
    POSITION,
    ROLL,
    STATE_NAMES,
    STATE_SIZE,
    TILT,
    angles_from_rotations,
    project_state,
    rotation_and_derivatives,
    rotation_x,
    rotation_z,
)

W, H = 960, 540


def random_state(rng) -> np.ndarray:
    """A broadcast-like camera: above the near touchline, looking at the pitch."""
    return np.array([
        rng.uniform(600.0, 3000.0),
        rng.uniform(-0.2, 0.05),
        math.radians(rng.uniform(-50.0, 50.0)),
        math.radians(rng.uniform(60.0, 80.0)),
        math.radians(rng.uniform(-2.0, 2.0)),
        rng.uniform(-10.0, 10.0),
        rng.uniform(45.0, 60.0),
        rng.uniform(-20.0, -8.0),
    ])


def test_names_order_and_indices():
    assert STATE_NAMES == ("f_px", "k1", "pan_rad", "tilt_rad", "roll_rad", "Cx_m", "Cy_m", "Cz_m")
    assert STATE_SIZE == 8
    assert [STATE_NAMES[i] for i in (FOCAL, K1, PAN, TILT, ROLL)] == ["f_px", "k1", "pan_rad", "tilt_rad", "roll_rad"]
    assert STATE_NAMES[ANGLES] == ("pan_rad", "tilt_rad", "roll_rad")
    assert STATE_NAMES[POSITION] == ("Cx_m", "Cy_m", "Cz_m")


def test_camera_vector_round_trip_is_exact():
    rng = np.random.default_rng(11)
    for _ in range(20):
        state = random_state(rng)
        camera = Camera.from_vector(state, W, H)
        assert camera.focal_px == state[FOCAL] and camera.k1 == state[K1]
        assert (camera.pan_rad, camera.tilt_rad, camera.roll_rad) == tuple(state[ANGLES])
        np.testing.assert_array_equal(camera.position_m, state[POSITION])
        np.testing.assert_array_equal(camera.to_vector(), state)
        again = Camera.from_vector(camera.to_vector(), W, H)
        np.testing.assert_array_equal(again.R_cw, camera.R_cw)


def test_project_state_agrees_with_camera_project_on_random_points():
    rng = np.random.default_rng(5)
    for _ in range(20):
        state = random_state(rng)
        camera = Camera.from_vector(state, W, H)
        # Pitch points, raised points, and points behind the camera (beyond the touchline).
        points = np.column_stack([rng.uniform(-60, 60, 200), rng.uniform(-40, 80, 200), rng.uniform(-3, 0, 200)])
        uv, _, in_front = project_state(state, points, W, H, want_jacobian=False)
        uv_with_jacobian, _, in_front_with_jacobian = project_state(state, points, W, H)
        np.testing.assert_array_equal(uv, uv_with_jacobian)  # the rotation alone, or with its derivatives
        np.testing.assert_array_equal(in_front, in_front_with_jacobian)
        expected, front = camera.project(points)
        np.testing.assert_array_equal(in_front, front)
        assert (~in_front).any() and in_front.any()
        np.testing.assert_allclose(uv[in_front], expected[in_front], rtol=1e-12, atol=1e-9)
        assert np.all(np.isfinite(uv))  # behind the camera: finite dummies, no NaN
        points_c = camera.world_to_camera(points)
        depth = points_c[:, 2]
        with np.errstate(invalid="ignore", divide="ignore"):
            radius2 = np.sum((points_c[:, :2] / depth[:, None]) ** 2, axis=1)
        # Behind the camera, or (k1 < 0) beyond the radius where the distortion folds points back.
        np.testing.assert_array_equal(in_front, (depth > BEHIND_CAMERA_Z) & (radius2 < unfolded_radius2(state[1])))


def test_points_beyond_the_fold_radius_are_not_projected_into_the_image():
    # k1 = -0.04 at f = 760: points whose undistorted radius passes 1 / sqrt(3 |k1|) (about 3.5 image
    # widths from the centre) would come back into the image. They are reported as not projectable.
    state = np.array([760.0, -0.04, 0.38, 1.18, 0.0, 1.9, 59.3, -16.8])
    camera = Camera.from_vector(state, 640, 360)
    x_far = np.linspace(-60.0, 60.0, 2001)
    goal_line = np.column_stack([np.full_like(x_far, -52.5), np.linspace(-34.0, 34.0, 2001), np.zeros(2001)])
    uv, front = camera.project(goal_line)
    _, _, front_state = project_state(state, goal_line, 640, 360, want_jacobian=False)
    np.testing.assert_array_equal(front, front_state)
    depth = camera.world_to_camera(goal_line)[:, 2]
    folded = (depth > BEHIND_CAMERA_Z) & ~front
    assert folded.any()  # this goal line passes close beside the camera: part of it is beyond the fold
    assert not camera.in_image(uv[front]).any()  # what is left stays off the image, as it should
    assert np.all(np.isnan(uv[~front]))


def test_jacobian_is_zero_behind_the_camera_and_has_state_columns():
    state = np.array([1000.0, -0.05, 0.1, math.radians(70.0), 0.0, 0.0, 55.0, -12.0])
    points = np.array([[0.0, 0.0, 0.0], [0.0, 80.0, 0.0]])  # in front; behind (beyond the camera)
    _, J, in_front = project_state(state, points, W, H)
    assert in_front.tolist() == [True, False]
    assert J.shape == (2, 2, STATE_SIZE) and not J[1].any()
    # d uv / d f = (1 + k1 r^2) x_n = (uv - principal point) / f.
    uv, _, _ = project_state(state, points[:1], W, H)
    np.testing.assert_allclose(J[0, :, FOCAL], (uv[0] - [W / 2, H / 2]) / state[FOCAL], rtol=1e-12)


def test_one_rotation_for_camera_and_state():
    rng = np.random.default_rng(2)
    for pan, tilt, roll in rng.uniform(-math.pi, math.pi, (20, 3)):
        R, dR = rotation_and_derivatives(pan, tilt, roll)
        np.testing.assert_array_equal(R, rotation_from_angles(pan, tilt, roll))
        np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-15)
        step = 1e-6
        for i in range(3):
            angles = np.array([pan, tilt, roll])
            plus, minus = angles.copy(), angles.copy()
            plus[i] += step
            minus[i] -= step
            numeric = (rotation_from_angles(*plus) - rotation_from_angles(*minus)) / (2 * step)
            np.testing.assert_allclose(dR[i], numeric, atol=1e-9)


def test_rotation_builders_by_hand():
    # Rz(90 deg) turns x into y; Rx(90 deg) turns y into z.
    np.testing.assert_allclose(rotation_z(math.pi / 2) @ [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], atol=1e-15)
    np.testing.assert_allclose(rotation_x(math.pi / 2) @ [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], atol=1e-15)
    np.testing.assert_array_equal(rotation_z(0.0), np.eye(3))


def test_angles_of_many_rotations_at_once_are_those_of_each():
    rng = np.random.default_rng(0)
    angles = rng.uniform(-3.1, 3.1, (200, 3))
    angles[:5, 1] = 0.0  # gimbal lock: tilt 0 ...
    angles[5:10, 1] = np.pi  # ... and 180 deg
    R = np.stack([rotation_from_angles(*a) for a in angles])
    expected = np.array([angles_from_rotation(r) for r in R])
    np.testing.assert_allclose(angles_from_rotations(R), expected, rtol=0, atol=1e-12)
    np.testing.assert_allclose(np.stack([rotation_from_angles(*a) for a in angles_from_rotations(R)]), R, atol=1e-12)
