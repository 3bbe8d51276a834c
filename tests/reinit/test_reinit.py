"""Re-initialisation: two-point method, homography decomposition, search + fit, keypoint RANSAC, line fitting."""

from __future__ import annotations

import math

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.template import TemplateCurves, TemplateSampling
from broadtrack_graph.reinit.linefit import LineFitConfig, fit_camera_to_lines
from broadtrack_graph.reinit.lines import (
    camera_from_homography, camera_from_two_points, focal_from_ray_angle, homography_from_lines,
    reinit_from_keypoints, reinit_from_lines, score_labelled,
)
from broadtrack_graph.geometry.pitch import PitchTemplate

W, H = 960, 540
PITCH = PitchTemplate()
CURVES = TemplateCurves(PITCH)
SAMPLING = TemplateSampling(PITCH)


def _camera(pan=-12.0, tilt=76.0, focal=1100.0, k1=0.0, position=(1.5, 57.0, -13.0), roll=0.3):
    return Camera.from_degrees(focal, k1, pan, tilt, roll, position, W, H)


def _lines(camera, rng=None, noise_px=0.0, per_class=12):
    """Visible template classes as labelled points (like an annotation)."""
    out = {}
    for name, pts in PITCH.sample_uniform(0.5).items():
        uv, front = camera.project(pts)
        ok = front & camera.in_image(uv)
        if ok.sum() < 4:
            continue
        sel = uv[ok][np.linspace(0, ok.sum() - 1, per_class).astype(int)]
        if rng is not None:
            sel = sel + rng.normal(0, noise_px, sel.shape)
        out[name] = sel
    return out


def test_focal_from_ray_angle_inverts_the_angle():
    uv = np.array([[100.0, 200.0], [800.0, 350.0]])
    for focal in (500.0, 1500.0, 4000.0):
        a = np.array([uv[0, 0] - W / 2, uv[0, 1] - H / 2, focal])
        b = np.array([uv[1, 0] - W / 2, uv[1, 1] - H / 2, focal])
        angle = math.acos(a @ b / np.linalg.norm(a) / np.linalg.norm(b))
        assert focal_from_ray_angle(uv, angle, W, H) == pytest.approx(focal, rel=1e-6)
    assert focal_from_ray_angle(uv, math.radians(179), W, H) is None


def test_two_point_method_recovers_a_roll_free_camera():
    truth = _camera(roll=0.0, position=(0.0, 55.0, -12.0))
    points_w = np.array([[-20.0, 10.0, 0.0], [15.0, -20.0, 0.0]])
    uv, _ = truth.project(points_w)
    camera = camera_from_two_points(uv, points_w, truth.position_m, W, H)
    assert camera.focal_px == pytest.approx(truth.focal_px, rel=1e-3)
    assert camera.pan_deg == pytest.approx(truth.pan_deg, abs=0.05)
    assert camera.tilt_deg == pytest.approx(truth.tilt_deg, abs=0.05)
    assert camera.roll_rad == 0.0
    assert camera_from_two_points(uv[[0, 0]], points_w[[0, 0]], truth.position_m, W, H) is None


def test_homography_decomposition_recovers_the_camera():
    truth = _camera(k1=0.0)
    lines = _lines(truth)
    Hmat = homography_from_lines(lines, PITCH)
    assert Hmat is not None
    camera = camera_from_homography(Hmat, W, H)
    assert camera.focal_px == pytest.approx(truth.focal_px, rel=0.01)
    np.testing.assert_allclose(camera.position_m, truth.position_m, atol=0.3)
    assert camera.pan_deg == pytest.approx(truth.pan_deg, abs=0.1)
    assert homography_from_lines({k: v for k, v in list(lines.items())[:2]}, PITCH) is None


def test_fit_camera_to_lines_converges_from_a_perturbed_start():
    truth = _camera(k1=0.04)
    lines = _lines(truth, np.random.default_rng(1), noise_px=0.3)
    start = truth.replace(pan_rad=truth.pan_rad + 0.02, tilt_rad=truth.tilt_rad - 0.01, focal_px=truth.focal_px * 1.08,
                          k1=0.0)
    result = fit_camera_to_lines(start, lines, CURVES, LineFitConfig())
    assert 0.0 < result.max_distance_px < 1.5
    assert result.camera.focal_px == pytest.approx(truth.focal_px, rel=0.03)
    assert result.camera.pan_deg == pytest.approx(truth.pan_deg, abs=0.2)


@pytest.mark.parametrize("case", [
    dict(pan=-12.0, tilt=76.0, focal=1100.0, position=(1.5, 57.0, -13.0)),  # wide, many lines
    dict(pan=28.0, tilt=74.0, focal=1900.0, position=(-2.0, 60.0, -15.0)),  # right penalty area
])
def test_reinit_from_lines_reaches_every_class(case):
    truth = _camera(**case)
    lines = _lines(truth, np.random.default_rng(2), noise_px=0.5)
    result = reinit_from_lines(lines, W, H, PITCH, curves=CURVES, sampling=SAMPLING)
    assert result.camera is not None
    score = score_labelled(result.camera, lines, 5.0, SAMPLING)
    assert score.fn == 0 and score.inlier_share == 1.0
    np.testing.assert_allclose(result.camera.position_m, truth.position_m, atol=3.0)


def test_reinit_from_lines_without_usable_class_is_none():
    result = reinit_from_lines({"Line unknown": np.zeros((3, 2))}, W, H, PITCH, curves=CURVES, sampling=SAMPLING)
    assert result.camera is None and result.reason


def test_reinit_from_keypoints_ransac_rejects_outliers():
    truth = _camera(roll=0.0, position=(0.0, 55.0, -12.0))
    names = [n for n in PITCH.keypoints if PITCH.is_on_ground(n.split(" | ")[0].split(" (")[0])]
    pts = PITCH.keypoint_array(names)
    uv, front = truth.project(pts)
    ok = front & truth.in_image(uv)
    uv, pts = uv[ok], pts[ok]
    assert len(uv) >= 5
    rng = np.random.default_rng(3)
    uv_noisy = uv + rng.normal(0, 0.5, uv.shape)
    uv_noisy[:2] += 150.0  # two gross outliers
    result = reinit_from_keypoints(uv_noisy, pts, W, H)
    assert result.camera is not None
    assert result.camera.pan_deg == pytest.approx(truth.pan_deg, abs=0.3)
    assert result.camera.focal_px == pytest.approx(truth.focal_px, rel=0.03)
    assert result.score.inlier_share == pytest.approx((len(uv) - 2) / len(uv))


# --------------------------------------------------------------------------- weight-free: from the marking map


def _median_template_error_px(camera, truth):
    """Median pixel distance between the ground template (1 m samples) seen by truth and by camera."""
    samples = np.vstack([p for n, p in PITCH.sample_uniform(1.0).items() if PITCH.is_on_ground(n)])
    uv_true, front = truth.project(samples)
    shown = front & truth.in_image(uv_true)
    uv, _ = camera.project(samples[shown])
    return float(np.nanmedian(np.linalg.norm(uv - uv_true[shown], axis=1)))


def test_marking_lines_finds_the_drawn_lines_not_the_specks():
    import cv2

    from broadtrack_graph.reinit.mask import marking_lines

    mask = np.zeros((540, 960), np.uint8)
    drawn = [((40, 100), (900, 140)), ((300, 520), (620, 60)), ((100, 400), (500, 420))]
    for a, b in drawn:
        cv2.line(mask, a, b, 1, 1)
    rng = np.random.default_rng(4)
    for x, y in rng.integers([0, 0], [960, 540], size=(60, 2)):  # grass specks: 2 px each
        mask[y, x: x + 2] = 1
    lines = marking_lines(mask > 0, 1920)  # frame twice the map's width
    assert len(lines) == 3
    for a, b in drawn:
        a2, b2 = 2 * np.array(a, float), 2 * np.array(b, float)
        best = min(lines, key=lambda line: abs(line.normal @ a2 + line.offset_px) + abs(line.normal @ b2 + line.offset_px))
        assert abs(best.normal @ a2 + best.offset_px) < 3.0 and abs(best.normal @ b2 + best.offset_px) < 3.0
        assert 0.6 * np.linalg.norm(b2 - a2) < best.support_px < 1.3 * np.linalg.norm(b2 - a2)


def test_line_pair_cameras_contain_a_tight_roll_free_camera():
    from broadtrack_graph.reinit.mask import ImageLine, line_pair_cameras

    truth = Camera.from_degrees(2.25 * 1920, 0.0, 10.6, 79.6, 0.0, (0.0, 55.0, -12.0), 1920, 1080)
    lines = []
    for name in ("Middle line", "Side line top"):
        uv, front = truth.project(PITCH.sample_uniform(0.5)[name])
        uv = uv[front & truth.in_image(uv)]
        centre = uv.mean(axis=0)
        direction = np.linalg.svd(uv - centre)[2][0]
        normal = np.array([-direction[1], direction[0]])
        along = (uv - centre) @ direction
        lines.append(ImageLine(normal, float(-normal @ centre), centre, direction,
                               (float(along.min()), float(along.max())), float(np.ptp(along))))
    pairs = line_pair_cameras(lines, (0.0, 55.0, -12.0), (1920, 1080), PITCH)
    assert 0 < len(pairs.focals_px) < 500
    errors = [_median_template_error_px(Camera(f, 0.0, p, t, 0.0, np.array([0.0, 55.0, -12.0]), 1920, 1080), truth)
              for p, t, f in zip(pairs.pans_rad, pairs.tilts_rad, pairs.focals_px)]
    # f is gridded (4 % steps): the closest camera is within a grid step of the truth, not exactly on it.
    assert 0.0 < min(errors) < 15.0


def test_pointing_turns_a_direction_onto_a_ray_with_roll_zero():
    from broadtrack_graph.reinit.mask import _pointing

    truth = Camera.from_degrees(2000.0, 0.0, 14.0, 77.0, 0.0, (0.0, 55.0, -12.0), 1920, 1080)
    point_w = np.array([8.0, -5.0, 0.0])
    uv, _ = truth.project(point_w[None])
    ray_c = np.array([uv[0, 0] - 960.0, uv[0, 1] - 540.0, 2000.0])
    solutions = _pointing(point_w - truth.position_m, ray_c)
    assert len(solutions) == 2
    pan, tilt = min(solutions, key=lambda pt: abs(pt[0] - truth.pan_rad))
    assert math.degrees(pan) == pytest.approx(14.0, abs=1e-6) and math.degrees(tilt) == pytest.approx(77.0, abs=1e-6)


@pytest.fixture(scope="module")
def hard_frames():
    """Two rendered frames of the `hard` preset at 1920x1080, zoomed to f = 2.25 W, and their weight-free detections."""
    from broadtrack_graph.detect.weightfree import WeightFreeDetector
    from broadtrack_graph.synth.clip import render_clip
    from broadtrack_graph.synth.motion import generate_camera_track

    track = generate_camera_track("hard", 40, 1920, 1080, seed=7)
    out = []
    detector = WeightFreeDetector(PITCH)
    for index in (8, 26):  # the right penalty area from afar; the centre circle with the middle line
        frame = render_clip("hard", 1, 1920, 1080, seed=7, cameras=[track.cameras[index]]).frames[0]
        out.append((frame.camera, detector.detect(frame.image)))
    return out


@pytest.mark.parametrize("which", [0, 1])
def test_reinit_from_mask_finds_a_tight_zoom_on_a_rendered_hard_frame(hard_frames, which):
    from broadtrack_graph.reinit.mask import reinit_from_mask

    truth, det = hard_frames[which]
    assert truth.focal_px > 2.2 * 1920  # about 25 deg of field of view: a coarse pan/tilt grid misses it
    # The default tripod guesses, not the true focal point (which is ~0.3 m from the main one here).
    result = reinit_from_mask(det.marking_mask, det.marking_points_px, (1920, 1080), PITCH, curves=CURVES,
                              field_mask=det.field_mask)
    assert result.camera is not None
    assert 0.0 < _median_template_error_px(result.camera, truth) < 2.0
    assert 0.7 < result.score.jaccard <= 1.0


def test_reinit_from_mask_on_the_real_broadcast_frame():
    """The real frame is a main-camera view of the right penalty area from far back (a stadium with a track)."""
    import pathlib

    import cv2

    from broadtrack_graph.reinit.mask import reinit_from_mask
    from broadtrack_graph.detect.weightfree import WeightFreeDetector

    path = pathlib.Path(__file__).resolve().parents[3] / "shared/data/real-frames/broadcast-frame-1073x603.png"
    if not path.exists():
        pytest.skip(f"{path} not available")
    image = cv2.imread(str(path))
    det = WeightFreeDetector(PITCH).detect(image)
    result = reinit_from_mask(det.marking_mask, det.marking_points_px, (image.shape[1], image.shape[0]), PITCH,
                              curves=CURVES, field_mask=det.field_mask)
    camera = result.camera
    assert camera is not None and 0.65 < result.score.jaccard <= 1.0
    # Looking at the right goal from the near side: the penalty spot is in the picture, the centre spot is not.
    uv, front = camera.project(np.array([[41.5, 0.0, 0.0], [0.0, 0.0, 0.0]]))
    assert front[0] and camera.in_image(uv[:1])[0] and not camera.in_image(uv[1:])[0]
    assert 10.0 < camera.pan_deg < 40.0 and 75.0 < camera.tilt_deg < 85.0
    assert camera.position_m[1] > 40.0 and camera.position_m[2] < -8.0  # behind the near touchline, above the pitch
