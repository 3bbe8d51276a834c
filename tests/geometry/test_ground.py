import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.ground import (
    GROUND_ABOVE_HORIZON,
    GROUND_NOT_FINITE,
    GROUND_OK,
    ground_covariance,
    ground_jacobians,
    ground_points,
)


def _camera(k1=-0.08):
    return Camera.from_degrees(2200.0, k1, 10.0, 75.0, 0.5, [0.0, 55.0, -18.0], 1920, 1080)


def test_round_trip_with_distortion():
    camera = _camera(k1=-0.08)
    rng = np.random.default_rng(0)
    truth = np.column_stack([rng.uniform(-30, 30, 50), rng.uniform(-20, 30, 50), np.zeros(50)])
    uv, in_front = camera.project(truth)
    keep = in_front & camera.in_image(uv)
    assert keep.sum() > 10
    xy, reasons = ground_points(camera, uv[keep])
    assert all(r == GROUND_OK for r in reasons)
    np.testing.assert_allclose(xy, truth[keep, :2], atol=1e-6)


def test_rejects_horizon_and_nan():
    camera = _camera()
    xy, reasons = ground_points(camera, np.array([[960.0, -3000.0], [np.nan, 5.0], [960.0, 900.0]]))
    assert reasons[0] == GROUND_ABOVE_HORIZON or reasons[0] != GROUND_OK
    assert reasons[1] == GROUND_NOT_FINITE
    assert reasons[2] == GROUND_OK and np.isfinite(xy[2]).all()
    assert np.isnan(xy[:2]).all()


def test_jacobians_against_finite_differences():
    camera = _camera()
    uv = np.array([[400.0, 700.0], [1500.0, 900.0], [960.0, 400.0]])
    xy, _ = ground_points(camera, uv)
    state = camera.to_vector()
    A, B = ground_jacobians(state, xy, 1920, 1080)
    steps = np.array([1.0, 1e-4, 1e-6, 1e-6, 1e-6, 1e-4, 1e-4, 1e-4])
    for k in range(8):
        plus, minus = state.copy(), state.copy()
        plus[k] += steps[k]
        minus[k] -= steps[k]
        xp, _ = ground_points(Camera.from_vector(plus, 1920, 1080), uv)
        xm, _ = ground_points(Camera.from_vector(minus, 1920, 1080), uv)
        numeric = (xp - xm) / (2 * steps[k])
        np.testing.assert_allclose(A[:, :, k], numeric, rtol=1e-4, atol=1e-5)
    for k in range(2):
        d = np.zeros(2)
        d[k] = 1e-3
        numeric = (ground_points(camera, uv + d)[0] - ground_points(camera, uv - d)[0]) / 2e-3
        np.testing.assert_allclose(B[:, :, k], numeric, rtol=1e-4, atol=1e-7)


def test_covariance_against_monte_carlo():
    camera = _camera()
    uv = np.array([[700.0, 800.0]])
    xy, _ = ground_points(camera, uv)
    state = camera.to_vector()
    sigma = np.array([15.0, 0.005, np.radians(0.02), np.radians(0.02), np.radians(0.01), 0.2, 0.2, 0.2])
    cov = ground_covariance(state, xy, 1920, 1080, np.diag(sigma ** 2), 2.0)[0]
    rng = np.random.default_rng(1)
    samples = []
    for _ in range(1500):
        s = state + rng.normal(0, sigma)
        p = uv + rng.normal(0, 2.0, size=2)
        samples.append(ground_points(Camera.from_vector(s, 1920, 1080), p)[0][0])
    mc = np.cov(np.array(samples).T)
    np.testing.assert_allclose(np.sqrt(np.diag(mc)), np.sqrt(np.diag(cov)), rtol=0.1)
