"""Analytic Jacobians of every factor against central finite differences, and the
gtsam wrappers' linearize() against the numpy functions."""

from __future__ import annotations

import gtsam
import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.state import project_state
from factors.flow import flow_residuals, make_flow_factor
from factors.keypoints import keypoint_residuals, make_keypoint_factor
from factors.lines import MarkingPolylines, line_residuals, make_line_factor
from factors.motion import random_walk_residuals, smoothness_residuals
from factors.priors import range_residuals
from factors.robust import INVALID_RESIDUAL_SIGMAS, cauchy_rows, robust_rows
from factors.tripod import tripod_residual

W, H = 960, 540
STEPS = np.array([1e-3, 1e-7, 1e-7, 1e-7, 1e-7, 1e-5, 1e-5, 1e-5])


def state_of(pan_deg=10.0, tilt_deg=72.0, roll_deg=0.5, focal_px=900.0, k1=-0.08, position=(2.0, 55.0, -15.0)):
    return np.array([focal_px, k1, *np.radians([pan_deg, tilt_deg, roll_deg]), *position])


def numeric_jacobian(fn, x, steps):
    x = np.asarray(x, dtype=float)
    columns = []
    for i in range(len(x)):
        dx = np.zeros(len(x))
        dx[i] = steps[i]
        columns.append((np.ravel(fn(x + dx)) - np.ravel(fn(x - dx))) / (2 * steps[i]))
    return np.stack(columns, axis=1)


def assert_jacobian_close(analytic, numeric, rel=1e-4):
    scale = np.maximum(np.abs(numeric).max(axis=0), 1e-6)
    assert np.all(np.abs(analytic - numeric) <= rel * scale + 1e-7), np.abs(analytic - numeric).max(axis=0) / scale


@pytest.fixture(scope="module")
def ground_points():
    rng = np.random.default_rng(3)
    return np.column_stack([rng.uniform(-20, 30, 40), rng.uniform(-10, 30, 40), np.zeros(40)])


def test_project_state_matches_camera_and_jacobian(ground_points):
    state = state_of()
    points = np.vstack([ground_points, [[-52.5, 3.66, -2.44]]])
    uv, J, in_front = project_state(state, points, W, H)
    expected, front = Camera.from_vector(state, W, H).project(points)
    assert in_front.all() and front.all()
    np.testing.assert_allclose(uv, expected, atol=1e-9)
    assert J.shape == (len(points), 2, 8)
    numeric = numeric_jacobian(lambda s: project_state(s, points, W, H, False)[0], state, STEPS)
    assert_jacobian_close(J.reshape(-1, 8), numeric)


def test_project_state_behind_camera_is_flagged():
    state = state_of()
    uv, J, in_front = project_state(state, np.array([[2.0, 80.0, 0.0], [0.0, 0.0, 0.0]]), W, H)
    assert list(in_front) == [False, True]
    assert np.all(np.isfinite(uv)) and np.all(J[0] == 0)


def test_line_residuals_distance_and_jacobian():
    pitch = PitchTemplate()
    polylines = MarkingPolylines.from_pitch(pitch)
    state = state_of()
    camera = Camera.from_vector(state, W, H)
    rng = np.random.default_rng(0)
    uv_list, cls_list = [], []
    for name in ("Middle line", "Circle central", "Side line top"):
        points = pitch.sample_uniform(0.37, classes=[name])[name]
        uv, front = camera.project(points)
        keep = front & camera.in_image(uv)
        uv = uv[keep][:: max(1, keep.sum() // 15)]
        uv_list.append(uv + rng.normal(0, 2.0, uv.shape))
        cls_list.append(np.full(len(uv), polylines.class_index(name)))
    uv_px, class_index = np.vstack(uv_list), np.concatenate(cls_list)
    r, (J,), valid = line_residuals(state, uv_px, class_index, polylines, W, H)
    assert valid.all() and J.shape == (len(uv_px), 8)
    # Distances are of the size of the injected noise (2 px), not zero and not large.
    assert 0.5 < np.sqrt(np.mean(r**2)) < 4.0
    numeric = numeric_jacobian(lambda s: line_residuals(s, uv_px, class_index, polylines, W, H, False)[0], state, STEPS)
    assert_jacobian_close(J, numeric, rel=1e-3)


def test_line_residual_noise_free_is_zero_and_invisible_class_invalid():
    pitch = PitchTemplate()
    polylines = MarkingPolylines.from_pitch(pitch, step_line_m=1.0)
    state = state_of()
    camera = Camera.from_vector(state, W, H)
    # Points sampled exactly on vertices of the polyline.
    vertices = polylines.vertices_w[polylines.class_index("Middle line")]
    uv, front = camera.project(vertices)
    keep = front & camera.in_image(uv)
    r, _, valid = line_residuals(state, uv[keep], np.full(keep.sum(), polylines.class_index("Middle line")), polylines, W, H)
    assert valid.all() and np.abs(r).max() < 1e-6
    # A class entirely behind the camera is reported invalid, not as zero.
    behind_state = state.copy()
    behind_state[2] = np.radians(180.0)
    r, _, valid = line_residuals(behind_state, np.array([[100.0, 100.0]]), np.array([polylines.class_index("Side line bottom")]), polylines, W, H)
    assert not valid.any()


def test_keypoint_jacobian(ground_points):
    state = state_of()
    uv = project_state(state, ground_points, W, H, False)[0] + 1.5
    r, (J,), valid = keypoint_residuals(state, uv, ground_points, W, H)
    np.testing.assert_allclose(r, -1.5, atol=1e-9)
    numeric = numeric_jacobian(lambda s: keypoint_residuals(s, uv, ground_points, W, H, False)[0], state, STEPS)
    assert_jacobian_close(J.reshape(-1, 8), numeric)


def test_flow_transfer_is_exact_and_jacobians_match(ground_points):
    s_prev = state_of()
    s_cur = state_of(pan_deg=10.4, tilt_deg=72.2, focal_px=910.0, position=(2.01, 55.0, -15.0))
    uv_prev = project_state(s_prev, ground_points, W, H, False)[0]
    uv_cur = project_state(s_cur, ground_points, W, H, False)[0]
    r, (J_prev, J_cur), valid = flow_residuals(s_prev, s_cur, uv_prev, uv_cur, W, H)
    assert valid.all()
    assert np.abs(r).max() < 1e-6  # ground points transfer exactly (distortion included)
    uv_cur_noisy = uv_cur + 0.7
    fn_prev = lambda s: flow_residuals(s, s_cur, uv_prev, uv_cur_noisy, W, H, False)[0]
    fn_cur = lambda s: flow_residuals(s_prev, s, uv_prev, uv_cur_noisy, W, H, False)[0]
    _, (J_prev, J_cur), _ = flow_residuals(s_prev, s_cur, uv_prev, uv_cur_noisy, W, H)
    assert_jacobian_close(J_prev.reshape(-1, 8), numeric_jacobian(fn_prev, s_prev, STEPS))
    assert_jacobian_close(J_cur.reshape(-1, 8), numeric_jacobian(fn_cur, s_cur, STEPS))
    # Camera t-1 held (the prediction of camera t): the same residuals and J_cur, no J_prev.
    r_held, (no_prev, J_cur_held), valid_held = flow_residuals(s_prev, s_cur, uv_prev, uv_cur_noisy, W, H,
                                                               previous_fixed=True)
    assert no_prev is None and valid_held.all()
    np.testing.assert_array_equal(r_held, flow_residuals(s_prev, s_cur, uv_prev, uv_cur_noisy, W, H)[0])
    np.testing.assert_array_equal(J_cur_held, J_cur)


def test_tripod_residual_zero_on_tripod_and_jacobians():
    from broadtrack_graph.geometry.camera import rotation_from_angles
    from broadtrack_graph.geometry.tripod import Tripod, focal_point

    tripod = Tripod((0.0, 56.0, -14.0), 0.3)
    state = state_of()
    R = rotation_from_angles(*state[2:5])
    state[5:8] = focal_point(R, tripod, 0.5)
    r, (Js, Jt), valid = tripod_residual(state, tripod.as_vector())
    assert r.shape == (1,) and abs(r[0]) < 1e-12 and valid is None
    state[5:8] += [0.05, -0.03, 0.02]
    t_vec = tripod.as_vector()
    r, (Js, Jt), _ = tripod_residual(state, t_vec)
    assert abs(r[0]) > 1e-3 and Js.shape == (1, 8) and Jt.shape == (1, 4)
    assert_jacobian_close(Js, numeric_jacobian(lambda s: tripod_residual(s, t_vec, False)[0], state, STEPS))
    assert_jacobian_close(Jt, numeric_jacobian(lambda t: tripod_residual(state, t, False)[0], t_vec, np.full(4, 1e-6)))


def test_motion_and_prior_jacobians():
    sigmas = np.array([0.01, 0.001, 0.002, 0.002, 0.001, 0.01, 0.01, 0.01])
    a, b, c = state_of(), state_of(pan_deg=10.3, focal_px=905.0), state_of(pan_deg=10.5, focal_px=912.0)
    r, (Jp, Jc), _ = random_walk_residuals(a, b, sigmas)
    assert_jacobian_close(Jp, numeric_jacobian(lambda s: random_walk_residuals(s, b, sigmas, False)[0], a, STEPS))
    assert_jacobian_close(Jc, numeric_jacobian(lambda s: random_walk_residuals(a, s, sigmas, False)[0], b, STEPS))
    s4 = np.array([0.001, 0.001, 0.001, 0.0005])
    r, Js, _ = smoothness_residuals(a, b, c, s4)
    for i, x in enumerate((a, b, c)):
        def fn(s, i=i):
            args = [a, b, c]
            args[i] = s
            return smoothness_residuals(*args, s4, False)[0]
        assert_jacobian_close(Js[i], numeric_jacobian(fn, x, STEPS))
    for f, k1 in ((900.0, -0.08), (50.0, -0.8), (9000.0, 0.7)):
        s = state_of(focal_px=f, k1=k1)
        args = ((200.0, 6000.0), (-0.5, 0.5), 0.05, 0.01, 0.0, 0.3)
        r, (J,), _ = range_residuals(s, *args)
        assert_jacobian_close(J, numeric_jacobian(lambda x: range_residuals(x, *args, False)[0], s, STEPS))
    assert range_residuals(state_of(), (200.0, 6000.0), (-0.5, 0.5), 0.05, 0.01, 0.0, 1e9)[0][:2].tolist() == [0.0, 0.0]


def test_cauchy_rows_cost_and_weights():
    residuals = np.array([[0.5, 0.0], [30.0, 40.0]])
    r_err, _ = cauchy_rows(residuals, None, 2.0)
    # 0.5 |r|^2 per row equals the Cauchy cost c^2/2 log(1 + e^2/c^2).
    np.testing.assert_allclose(0.5 * np.sum(r_err**2, axis=1), 2.0 * np.log1p(np.array([0.25, 2500.0]) / 4.0))
    J = np.ones((2, 2, 3))
    r_lin, (J_lin,) = cauchy_rows(residuals, [J], 2.0)
    weights = 1 / (1 + np.array([0.25, 2500.0]) / 4.0)
    np.testing.assert_allclose(J_lin[:, 0, 0], np.sqrt(weights))
    assert r_lin[1, 1] < 2.0  # the 50-sigma outlier is strongly down-weighted


def test_geman_mcclure_rows_cost_weights_and_the_pull_of_far_points():
    residuals = np.array([[0.5], [2.0], [20.0], [200.0]])
    e2 = residuals[:, 0] ** 2
    r_err, _ = robust_rows(residuals, None, 2.0, "geman-mcclure")
    # 0.5 |r|^2 per row equals the Geman-McClure cost c^2 e^2 / (2 (c^2 + e^2)), bounded by c^2 / 2.
    np.testing.assert_allclose(0.5 * np.sum(r_err**2, axis=1), 0.5 * 4.0 * e2 / (4.0 + e2))
    J = np.ones((4, 1, 3))
    r_lin, (J_lin,) = robust_rows(residuals, [J], 2.0, "geman-mcclure")
    np.testing.assert_allclose(J_lin[:, 0, 0], 4.0 / (4.0 + e2))  # sqrt of the weight c^4 / (c^2 + e^2)^2
    # The pull of a point (its weighted residual times its weighted Jacobian) falls with distance beyond the scale,
    # where Cauchy's keeps about c^2 / e: ten points 20 sigmas off pull less than one point 2 sigmas off.
    pull = r_lin[:, 0] * J_lin[:, 0, 0]
    assert 10 * pull[2] < pull[1] and pull[3] < pull[2]
    r_c, (J_c,) = cauchy_rows(residuals, [J], 2.0)
    assert 10 * r_c[2, 0] * J_c[2, 0, 0] > r_c[1, 0] * J_c[1, 0, 0]
    with pytest.raises(ValueError, match="unknown robust loss"):
        robust_rows(residuals, None, 2.0, "huber")


def test_gtsam_wrappers_linearize_like_numpy(ground_points):
    pitch = PitchTemplate()
    polylines = MarkingPolylines.from_pitch(pitch)
    s_prev, s_cur = state_of(), state_of(pan_deg=10.4)
    uv_prev = project_state(s_prev, ground_points, W, H, False)[0]
    uv_cur = project_state(s_cur, ground_points, W, H, False)[0] + 0.5
    values = gtsam.Values()
    values.insert(0, s_prev)
    values.insert(1, s_cur)
    flow = make_flow_factor(0, 1, uv_prev, uv_cur, W, H, 1.0, None)
    linear = flow.linearize(values)
    A, b = linear.jacobian()
    r, (Jp, Jc), _ = flow_residuals(s_prev, s_cur, uv_prev, uv_cur, W, H)
    np.testing.assert_allclose(A, np.hstack([Jp.reshape(-1, 8), Jc.reshape(-1, 8)]), rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(b, -r.reshape(-1), atol=1e-12)
    assert flow.error(values) == pytest.approx(0.5 * np.sum(r**2))
    # Keypoint factor with Cauchy: the error is the summed Cauchy cost.
    kp = make_keypoint_factor(1, uv_cur, ground_points, np.ones(len(uv_cur)), W, H, 1.0, 2.0)
    r_kp = keypoint_residuals(s_cur, uv_cur, ground_points, W, H, False)[0]
    expected = np.sum(2.0 * np.log1p(np.sum(r_kp**2, axis=1) / 4.0))
    assert kp.error(values) == pytest.approx(expected)
    lines = make_line_factor(1, uv_cur[:5], np.zeros(5, int), polylines, W, H, 1.0, 2.0)
    assert lines.linearize(values).jacobian()[0].shape == (5, 8)
    # Line factor with Geman-McClure: the error is the summed Geman-McClure cost of its points.
    gm = make_line_factor(1, uv_cur[:5], np.zeros(5, int), polylines, W, H, 1.0, 2.0, "geman-mcclure")
    r_line, _, valid = line_residuals(s_cur, uv_cur[:5], np.zeros(5, int), polylines, W, H, False)
    e2 = np.where(valid, r_line, INVALID_RESIDUAL_SIGMAS) ** 2
    assert gm.error(values) == pytest.approx(np.sum(0.5 * 4.0 * e2 / (4.0 + e2)))


def test_tripod_axis_point_model_zero_on_tripod_and_jacobians():
    from broadtrack_graph.geometry.camera import rotation_from_angles
    from broadtrack_graph.geometry.tripod import Tripod, focal_point
    from factors.tripod import tripod_axis_point_residuals

    tripod = Tripod((0.0, 56.0, -14.0), 0.3)
    state = state_of()
    state[5:8] = focal_point(rotation_from_angles(*state[2:5]), tripod, 0.7)
    t_vec = tripod.as_vector()
    r, _, _ = tripod_axis_point_residuals(state, t_vec)
    np.testing.assert_allclose(r, 0.0, atol=1e-12)
    state[5:8] += [0.05, -0.03, 0.02]
    r, (Js, Jt), _ = tripod_axis_point_residuals(state, t_vec)
    assert np.abs(r).max() > 1e-3
    assert_jacobian_close(Js, numeric_jacobian(lambda s: tripod_axis_point_residuals(s, t_vec, False)[0], state, STEPS))
    assert_jacobian_close(Jt, numeric_jacobian(lambda t: tripod_axis_point_residuals(state, t, False)[0], t_vec, np.full(4, 1e-6)))


def test_tripod_lambda_prior_measures_the_place_on_the_axis_with_jacobians():
    from broadtrack_graph.geometry.camera import rotation_from_angles
    from broadtrack_graph.geometry.tripod import Tripod, focal_point
    from factors.tripod import make_fixed_tripod_factor, tripod_axis_point_residuals

    tripod = Tripod((0.0, 56.0, -14.0), 0.3)
    state = state_of()
    R = rotation_from_angles(*state[2:5])
    state[5:8] = focal_point(R, tripod, 0.7)
    t_vec = tripod.as_vector()
    # On the tripod, lambda = 0.7: the third residual is weight * (0.7 - mean).
    r, _, _ = tripod_axis_point_residuals(state, t_vec, lambda_prior=(0.2, 4.0))
    np.testing.assert_allclose(r, [0.0, 0.0, 4.0 * 0.5], atol=1e-12)
    # Sliding C along the optical axis leaves the first two residuals at 0 and moves the third.
    state[5:8] += 1.5 * R[2]
    r, (Js, Jt), _ = tripod_axis_point_residuals(state, t_vec, lambda_prior=(0.2, 4.0))
    np.testing.assert_allclose(r, [0.0, 0.0, 4.0 * 2.0], atol=1e-9)
    state[5:8] += [0.05, -0.03, 0.02]
    r, (Js, Jt), _ = tripod_axis_point_residuals(state, t_vec, lambda_prior=(0.2, 4.0))
    assert Js.shape == (3, 8) and Jt.shape == (3, 4)
    fn = lambda s: tripod_axis_point_residuals(s, t_vec, False, (0.2, 4.0))[0]  # noqa: E731
    assert_jacobian_close(Js, numeric_jacobian(fn, state, STEPS))
    assert_jacobian_close(Jt, numeric_jacobian(lambda t: tripod_axis_point_residuals(state, t, False, (0.2, 4.0))[0],
                                               t_vec, np.full(4, 1e-6)))
    # The factor divides by sigma_m: lambda's own sigma is what remains.
    import gtsam

    factor = make_fixed_tripod_factor(0, t_vec, 0.02, "axis_point", lambda_prior_m=(0.2, 0.25))
    values = gtsam.Values()
    values.insert(0, state)
    whitened = factor.unwhitenedError(values)
    lam = R[2] @ (state[5:8] - t_vec[:3])
    assert whitened[2] == pytest.approx((lam - 0.2) / 0.25, rel=1e-9)


def test_line_residual_beyond_segment_end_is_distance_to_end_with_jacobian():
    pitch = PitchTemplate()
    polylines = MarkingPolylines.from_pitch(pitch)
    state = state_of(pan_deg=-30.0)
    j = polylines.class_index("Big rect. left main")
    vertices = polylines.vertices_w[j]
    uv, _, front = project_state(state, vertices[[-2, -1]], W, H, False)
    assert front.all()
    direction = (uv[1] - uv[0]) / np.linalg.norm(uv[1] - uv[0])
    normal = np.array([-direction[1], direction[0]])
    point = uv[1] + 6.0 * direction + 8.0 * normal  # past the end of the marking
    r, (J,), valid = line_residuals(state, point[None], np.array([j]), polylines, W, H)
    assert valid.all()
    assert abs(r[0]) == pytest.approx(10.0, rel=1e-6)  # distance to the end vertex: hypot(6, 8)
    numeric = numeric_jacobian(lambda s: line_residuals(s, point[None], np.array([j]), polylines, W, H, False)[0], state, STEPS)
    assert_jacobian_close(J, numeric, rel=1e-4)


def test_every_residual_function_returns_one_shape(ground_points):
    from factors.custom import Residuals
    from factors.priors import anchor_residuals
    from factors.tripod import tripod_axis_point_residuals

    pitch = PitchTemplate()
    polylines = MarkingPolylines.from_pitch(pitch, step_line_m=1.0)
    a, b, c = state_of(), state_of(pan_deg=10.3), state_of(pan_deg=10.5)
    uv = project_state(a, ground_points, W, H, False)[0]
    t_vec = np.array([0.0, 56.0, -14.0, 0.3])
    results = {
        "lines": (line_residuals(a, uv[:3], np.zeros(3, int), polylines, W, H), [8], 3),
        "keypoints": (keypoint_residuals(a, uv, ground_points, W, H), [8], len(uv)),
        "flow": (flow_residuals(a, b, uv, uv, W, H), [8, 8], len(uv)),
        "random walk": (random_walk_residuals(a, b, np.full(8, 0.01)), [8, 8], None),
        "smoothness": (smoothness_residuals(a, b, c, np.full(4, 0.01)), [8, 8, 8], None),
        "range": (range_residuals(a, (200.0, 6000.0), (-0.5, 0.5), 0.05, 0.01, 0.0, 1.0), [8], None),
        "anchor": (anchor_residuals(a, a, np.ones(8)), [8], None),
        "tripod distance": (tripod_residual(a, t_vec), [8, 4], None),
        "tripod axis point": (tripod_axis_point_residuals(a, t_vec), [8, 4], None),
    }
    for name, (result, sizes, points) in results.items():
        assert isinstance(result, Residuals), name
        assert [J.shape for J in result.jacobians] == [result.residual.shape + (n,) for n in sizes], name
        assert (result.valid is None) == (points is None), name
        if points is not None:
            assert result.valid.shape == (points,) and len(result.residual) == points, name
