"""Weight-free detector, mean-shift thinning, confidence and flow on small images drawn here."""

from __future__ import annotations

import cv2
import numpy as np
from drawn_frames import draw_frame

from broadtrack_graph.detect.detector import PredictedCamera, draw_detections
from broadtrack_graph.detect.flow import FlowConfig, flow_candidates, grid_flow, on_pitch, prepare
from broadtrack_graph.detect.meanshift import mean_shift_thin
from broadtrack_graph.detect.motion_blur import MotionBlurConfig
from broadtrack_graph.detect.template_raster import template_mask
from broadtrack_graph.detect.weightfree import WeightFreeDetector
from broadtrack_graph.detect.weightfree_config import WeightFreeConfig
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves, distances_to_polyline
from broadtrack_graph.reinit.confidence import DEFAULT_THRESHOLD, camera_confidence

W, H = 640, 360
PITCH = PitchTemplate()
FINE = TemplateCurves(PITCH, line_step_m=0.1, circle_step_m=0.05)


def _truth():
    return Camera.from_degrees(700.0, 0.0, -8.0, 74.0, 0.0, (0.0, 55.0, -12.0), W, H)


def test_mean_shift_thins_a_thick_band_to_its_centre():
    rng = np.random.default_rng(0)
    t = rng.uniform(0, 100, 3000)
    across = rng.uniform(-3, 3, 3000)
    points = np.column_stack([10 + t, 50 + 0.5 * t]) + np.outer(across, [-0.5, 1.0]) / np.hypot(0.5, 1.0)
    thin = mean_shift_thin(points, bandwidth_px=5.0, spacing_px=3.0)
    distance = np.abs((thin[:, 0] - 10) * 0.5 - (thin[:, 1] - 50)) / np.hypot(0.5, 1.0)
    inner = (thin[:, 0] > 15) & (thin[:, 0] < 105)
    assert np.max(distance[inner]) < 0.8 and np.mean(distance[inner]) < 0.2  # input spread is +-3 px
    assert 25 < len(thin) < 120
    assert mean_shift_thin(np.zeros((0, 2))).shape == (0, 2)


def test_detector_names_markings_within_a_pixel_and_finds_players():
    truth = _truth()
    image, boxes = draw_frame(truth)
    detector = WeightFreeDetector(PITCH, WeightFreeConfig(work_width_px=W))
    predicted = truth.replace(pan_rad=truth.pan_rad + 0.004)  # ~3 px off
    det = detector.detect(image, PredictedCamera(predicted, uncertainty_px=3.0))
    assert len(det.lines_px) >= 4
    errors = []
    for name, pts in det.lines_px.items():
        uv, front = truth.project(FINE.samples_w[name])
        errors.append(distances_to_polyline(pts, uv[front]))
    errors = np.concatenate(errors)
    assert len(errors) > 100
    assert np.mean(errors < 1.0) > 0.95
    assert det.marking_mask.shape == (H, W) and det.field_mask.shape == (H, W)
    # Most drawn players are found (boxes overlap).
    found = sum(any(b[0] <= p[2] and p[0] <= b[2] and b[1] <= p[3] and p[1] <= b[3] for b in det.player_boxes_px)
                for p in boxes)
    assert found >= 0.7 * len(boxes)
    # No named point on a player.
    for pts in det.lines_px.values():
        for x0, y0, x1, y1 in boxes:
            assert not np.any((pts[:, 0] > x0 + 1) & (pts[:, 0] < x1 - 1) & (pts[:, 1] > y0 + 1) & (pts[:, 1] < y1 - 1))
    # Observations for the graph: full-size marking map, the named points as they are.
    obs = det.to_observations(5)
    assert obs.marking_mask.shape == (H, W) and obs.line_point_count == sum(len(p) for p in det.lines_px.values())
    without_map = det.to_observations(5, with_marking_mask=False)  # the tracker's: it reads the detections' map
    assert without_map.marking_mask is None and without_map.lines_px.keys() == obs.lines_px.keys()
    picture = draw_detections(image, det, truth)
    assert picture.shape == image.shape and not np.array_equal(picture, image)
    # Without a prediction nothing is named, the map is still there.
    bare = detector.detect(image)
    assert bare.lines_px == {} and len(bare.marking_points_px) > 100


def test_found_markings_named_later_are_the_detection():
    truth = _truth()
    image, _ = draw_frame(truth)
    detector = WeightFreeDetector(PITCH, WeightFreeConfig(work_width_px=480))  # a working size of its own
    predicted = PredictedCamera(truth.replace(pan_rad=truth.pan_rad + 0.004), uncertainty_px=3.0)
    found = detector.find_markings(image)
    assert found.work_size == (480, 270) and found.scale == 0.75 and found.seconds > 0
    assert found.unnamed.lines_px == {} and found.unnamed.marking_mask.shape == (270, 480)
    whole, later = detector.detect(image, predicted), detector.name(found, predicted)
    assert later.lines_px.keys() == whole.lines_px.keys() and len(later.lines_px) >= 4
    for name, points in whole.lines_px.items():
        np.testing.assert_array_equal(later.lines_px[name], points)
    for mask in ("marking_mask", "field_mask", "player_mask"):
        np.testing.assert_array_equal(getattr(later, mask), getattr(whole, mask))
    np.testing.assert_array_equal(later.marking_points_px, whole.marking_points_px)
    np.testing.assert_array_equal(later.player_boxes_px, whole.player_boxes_px)
    assert later.info["work_scale"] == 0.75 and later.info["detect_ms"] >= 1000 * found.seconds
    # The named result is a new object: the found markings can be named again with another camera.
    assert found.unnamed.lines_px == {} and detector.name(found).lines_px == {}


def test_confidence_high_for_the_true_camera_low_for_a_wrong_one():
    truth = _truth()
    image, _ = draw_frame(truth, players=0)
    det = WeightFreeDetector(PITCH, WeightFreeConfig(work_width_px=W)).detect(image)
    curves = TemplateCurves(PITCH)
    good = camera_confidence(truth, det.marking_mask, curves, field_mask=det.field_mask)
    bad = camera_confidence(truth.replace(pan_rad=truth.pan_rad + 0.05), det.marking_mask, curves, field_mask=det.field_mask)
    assert good > 0.5 and good >= DEFAULT_THRESHOLD
    assert bad < DEFAULT_THRESHOLD and good - bad > 0.2
    assert camera_confidence(truth, np.zeros((H, W), bool), curves) == 0.0


def test_template_mask_draws_visible_markings_only():
    truth = _truth()
    mask = template_mask(truth, TemplateCurves(PITCH), W, H, 1)
    uv, front = truth.project(np.array([[0.0, 0.0, 0.0]]))  # centre spot lies on the middle line
    u, v = np.round(uv[0]).astype(int)
    assert mask[v - 1:v + 2, u - 1:u + 2].any()
    assert mask.mean() < 0.05


def test_flow_recovers_a_known_shift_and_respects_the_mask():
    rng = np.random.default_rng(4)
    texture = cv2.GaussianBlur(rng.integers(0, 255, (H + 20, W + 20, 3)).astype(np.uint8), (0, 0), 1.5)
    prev = texture[10:10 + H, 10:10 + W]
    cur = texture[7:7 + H, 12:12 + W]  # content moves by (-2, +3) px
    config = FlowConfig(work_width_px=W, grid_step_px=32)
    matches = grid_flow(prepare(prev, config), prepare(cur, config), W, H, config=config)
    assert len(matches) > 100
    np.testing.assert_allclose(np.median(matches.uv_cur_px - matches.uv_prev_px, axis=0), [-2.0, 3.0], atol=0.05)
    keep = np.zeros((H, W), bool)
    keep[:, : W // 2] = True
    half = grid_flow(prepare(prev, config), prepare(cur, config), W, H, keep_mask=keep, config=config)
    assert 0 < len(half) < len(matches) and np.all(half.uv_prev_px[:, 0] < W / 2)
    # With a camera, matches must back-project onto the pitch: the sky half of a looking-up camera is dropped.
    camera = Camera.from_degrees(700.0, 0.0, 0.0, 89.0, 0.0, (0.0, 55.0, -12.0), W, H)
    ground = grid_flow(prepare(prev, config), prepare(cur, config), W, H, prev_camera=camera, config=config)
    assert 0 < len(ground) < len(matches)
    points_w, hits = camera.ground_intersection(ground.uv_prev_px)
    assert hits.all() and np.all(np.abs(points_w[:, 1]) < 35.1)


def test_flow_computed_ahead_of_the_camera_is_the_same_flow():
    rng = np.random.default_rng(5)
    texture = cv2.GaussianBlur(rng.integers(0, 255, (H + 20, W + 20, 3)).astype(np.uint8), (0, 0), 1.5)
    prev, cur = texture[10:10 + H, 10:10 + W], texture[8:8 + H, 13:13 + W]
    config = FlowConfig(work_width_px=480, grid_step_px=24)  # working size below the frame's, as in a run
    keep = np.ones((H // 2, W // 2), bool)
    keep[:40, :] = keep[:, 250:] = False  # a reduced-size keep mask
    camera = Camera.from_degrees(700.0, 0.0, 0.0, 89.0, 0.0, (0.0, 55.0, -12.0), W, H)
    prev_frame, cur_frame = prepare(prev, config), prepare(cur, config)
    candidates = flow_candidates(prev_frame, cur_frame, W, H, keep, config)
    assert candidates.prev_frame is prev_frame and candidates.keep_mask is keep
    for kept in (keep, None):
        direct = grid_flow(prev_frame, cur_frame, W, H, camera, kept, config)
        ahead = on_pitch(flow_candidates(prev_frame, cur_frame, W, H, kept, config), camera, config)
        assert 0 < len(direct) < len(flow_candidates(prev_frame, cur_frame, W, H, kept, config).uv_prev_px)
        np.testing.assert_array_equal(ahead.uv_prev_px, direct.uv_prev_px)
        np.testing.assert_array_equal(ahead.uv_cur_px, direct.uv_cur_px)
        assert ahead.uv_prev_px.dtype == direct.uv_prev_px.dtype == np.float64


def test_reinit_from_the_marking_map_alone_finds_the_camera():
    from broadtrack_graph.reinit.mask import reinit_from_mask

    truth = _truth()
    image, _ = draw_frame(truth, seed=5, players=6)
    det = WeightFreeDetector(PITCH, WeightFreeConfig(work_width_px=W)).detect(image)
    result = reinit_from_mask(det.marking_mask, det.marking_points_px, (W, H), PITCH,
                              positions_w=[(0.0, 55.0, -12.0), (36.0, 55.0, -12.0)], field_mask=det.field_mask)
    assert result.camera is not None and result.score.jaccard > 0.5
    samples = np.vstack([p for n, p in PITCH.sample_uniform(2.0).items() if PITCH.is_on_ground(n)])
    uv_true, front = truth.project(samples)
    ok = front & truth.in_image(uv_true)
    uv_est, _ = result.camera.project(samples[ok])
    assert np.median(np.linalg.norm(uv_est - uv_true[ok], axis=1)) < 2.0
    empty = reinit_from_mask(np.zeros((H, W), bool), np.zeros((0, 2)), (W, H), PITCH)
    assert empty.camera is None and empty.reason


def test_no_point_is_named_inside_a_goal_or_after_a_marking_too_thin_to_see():
    from broadtrack_graph.geometry.goals import goal_region

    detector = WeightFreeDetector(PITCH)
    camera = Camera.from_degrees(1500.0, 0.0, -7.0, 72.0, 0.0, (53.0, 70.0, -22.0), 960, 540)  # beside the goal
    points = []
    for name in ("Side line right", "Big rect. right main"):
        uv, front = camera.project(FINE.samples_w[name])
        points.append(uv[front & camera.in_image(uv)])
    points = np.vstack(points)
    points = points[(points[:, 0] < 959) & (points[:, 1] < 539)]
    named = detector.name_points(points, PredictedCamera(camera, 1.0), 1.0, (960, 540))
    goals = goal_region(camera, 960, 540, PITCH)
    in_goal = goals[np.round(points[:, 1]).astype(int), np.round(points[:, 0]).astype(int)]
    assert in_goal.sum() > 10 and (~in_goal).sum() > 100
    named_all = np.vstack(list(named.values()))
    assert not goals[np.clip(np.round(named_all[:, 1]).astype(int), 0, 539),
                     np.clip(np.round(named_all[:, 0]).astype(int), 0, 959)].any()
    assert {"Side line right", "Big rect. right main"} <= set(named)
    # A marking thinner than min_named_width_px at its scale and min_named_paint_px across names nothing.
    thin = WeightFreeDetector(PITCH, WeightFreeConfig(min_named_width_px=50.0, min_named_paint_px=50.0))
    assert thin.name_points(points, PredictedCamera(camera, 1.0), 1.0, (960, 540)) == {}


def test_a_wide_views_far_lines_are_named_and_a_low_cameras_foreshortened_far_touchline_is_not():
    from broadtrack_graph.geometry.pitch import LINE_CLASSES
    from broadtrack_graph.geometry.template import project_template

    detector = WeightFreeDetector(PITCH)
    config = detector.config

    def points_on(camera, classes):
        points = []
        for name in classes:
            uv, front = camera.project(FINE.samples_w[name])
            points.append(uv[front & camera.in_image(uv)])
        return np.vstack(points)

    def widths(camera, name):  # (at its scale, its paint across) of a class's projected samples, working pixels
        template = project_template(camera, detector.curves, 960, 540, 0.5, paint_widths=True)
        of = template.class_index == LINE_CLASSES.index(name)
        return template.width_m_px[of], template.paint_width_px[of]

    # A camera 48 m up, 110 m from the centre spot and 60 deg wide: the lines under 1.4 px wide at their scale, their
    # paint 0.29 px and more across the image, seen face on: named (by their paint alone).
    far = Camera.from_degrees(830.0, 0.0, -30.0, 64.0, 0.0, (55.0, 95.0, -48.0), 960, 540)
    classes = ("Middle line", "Circle central", "Big rect. left main")
    for name in classes:
        at_scale, paint = widths(far, name)
        assert len(at_scale) > 50 and at_scale.max() < config.min_named_width_px
        assert paint.min() >= config.min_named_paint_px
    points = points_on(far, classes)
    assert set(classes) <= set(detector.name_points(points, PredictedCamera(far, 1.0), 1.0, (960, 540)))
    by_scale_only = WeightFreeDetector(PITCH, WeightFreeConfig(min_named_paint_px=50.0))
    assert by_scale_only.name_points(points, PredictedCamera(far, 1.0), 1.0, (960, 540)) == {}
    # A camera 5.5 m up, 7 m behind the near touchline: the far touchline under 1.4 px at its scale and its paint,
    # foreshortened, a tenth of a pixel across: not named (a ridge there is the boards' base), the halfway line is.
    low = Camera.from_degrees(800.0, 0.0, 0.0, 85.0, 0.0, (0.0, 41.0, -5.5), 960, 540)
    at_scale, paint = widths(low, "Side line top")
    assert len(at_scale) > 100 and at_scale.max() < config.min_named_width_px and paint.max() < 0.15
    named = detector.name_points(points_on(low, ("Side line top", "Middle line")), PredictedCamera(low, 1.0), 1.0,
                                 (960, 540))
    assert "Middle line" in named and "Side line top" not in named


def test_the_working_image_made_ahead_gives_the_same_markings():
    truth = Camera.from_degrees(1400.0, 0.0, -8.0, 74.0, 0.0, (0.0, 55.0, -12.0), 1920, 1080)
    image, _ = draw_frame(truth)
    detector = WeightFreeDetector(PITCH)
    working = detector.area_working_image(image)
    assert working.shape == (540, 960, 3)
    alone, ahead = detector.find_markings(image), detector.find_markings(image, working)
    for mask in ("marking_mask", "field_mask", "player_mask"):
        np.testing.assert_array_equal(getattr(ahead.unnamed, mask), getattr(alone.unnamed, mask))
    np.testing.assert_array_equal(ahead.unnamed.marking_points_px, alone.unnamed.marking_points_px)
    assert len(alone.unnamed.marking_points_px) > 100
    # Under twice the working width the working image is no area reduction: the frame itself is reduced.
    assert detector.area_working_image(cv2.resize(image, (1280, 720))) is None


def _classes_one_by_one(points_px, classes, distance_px, c):
    """The naming's class rule written plainly, one class at a time (np.median, point_cells.capped_cell_means)."""
    from broadtrack_graph.detect.point_cells import capped_cell_means
    from broadtrack_graph.geometry.pitch import LINE_CLASSES

    out = {}
    for j in np.unique(classes):
        members = classes == j
        dj = distance_px[members]
        median = np.median(dj)
        spread = max(c.class_consistency_px, 2.5 * 1.4826 * np.median(np.abs(dj - median)))
        keep = np.flatnonzero(members)[np.abs(dj - median) <= spread]
        if len(keep) >= c.min_points_per_class:
            out[LINE_CLASSES[j]] = capped_cell_means(points_px[keep], c.point_spacing_px, c.max_points_per_class)
    return out


def test_all_classes_at_once_name_the_same_points_as_one_class_at_a_time():
    from broadtrack_graph.detect.class_points import consistent_classes
    from broadtrack_graph.geometry.pitch import LINE_CLASSES

    config = WeightFreeConfig()
    rng = np.random.default_rng(1)
    for _ in range(300):
        n = int(rng.integers(0, 600))
        points = rng.uniform(-2.0, 962.0, (n, 2))  # a sub-pixel centre may lie just off the image
        classes = rng.integers(0, int(rng.integers(1, len(LINE_CLASSES) + 1)), n)
        distance = np.round(rng.gamma(2.0, 1.0, n), int(rng.integers(0, 4)))  # rounded: ties in the medians
        expected = _classes_one_by_one(points, classes, distance, config)
        got = consistent_classes(points, classes, distance, config.class_consistency_px, config.min_points_per_class,
                                 config.point_spacing_px, config.max_points_per_class)
        assert list(got) == list(expected)
        assert all(np.array_equal(got[name], expected[name]) for name in expected)


def _zoomed_frame(hfov_deg: float):
    """A main camera's view of a penalty area at hfov_deg, rendered with the markings' true width (1280x720)."""
    from broadtrack_graph.geometry.aim import aim_angles
    from broadtrack_graph.synth.field_samples import render_look
    from broadtrack_graph.synth.named_looks import draw_named_look, named_look

    position, aim = np.array([0.0, 55.0, -14.0]), np.array([-36.0, -10.0, 0.0])
    pan, tilt = aim_angles(position, aim)
    camera = Camera(640.0 / np.tan(np.radians(hfov_deg / 2)), 0.0, pan, tilt, 0.0, position, 1280, 720)
    look = draw_named_look("clean", np.random.default_rng(1), aim)
    return camera, render_look(camera, None, look, named_look("clean")).image


def _template_recall(camera, marking_mask) -> float:
    """Share of the camera's projected template (at the map's size) within 2 px of a marking pixel."""
    from scipy.spatial import cKDTree

    from broadtrack_graph.geometry.template import project_template

    h, w = marking_mask.shape
    template = project_template(camera.rescaled(w, h), TemplateCurves(PITCH), w, h, 0.5)
    marks = np.column_stack(np.nonzero(marking_mask)[::-1])
    return float(np.mean(cKDTree(marks).query(template.uv_px)[0] < 2.0))


def test_a_zoomed_view_is_named_from_its_wide_markings_and_a_wide_one_from_the_map_as_found():
    # At 5 deg the markings are about 17 px wide at the working size: the predicted camera asks for the reduced
    # levels, and the frame's map then lays the template on the lines' centres; at 30 deg (3 px) the map is the
    # camera-free one, the same pixels.
    # A wide marking's two edges look like a smear across it (detect/motion_blur.py reads this sharp frame smeared
    # along the wide line's normal, as long as the line is wide): the reduced levels' need is shown without the smear
    # undone, the naming with the default detector.
    detector = WeightFreeDetector(PITCH)
    camera, image = _zoomed_frame(5.0)
    named = detector.name(detector.find_markings(image), PredictedCamera(camera, 2.0))
    assert _template_recall(camera, named.marking_mask) > 0.95
    assert sum(len(p) for p in named.lines_px.values()) > 0
    smear_kept = WeightFreeDetector(PITCH, WeightFreeConfig(motion_blur=MotionBlurConfig(min_length_px=0)))
    found = smear_kept.find_markings(image)
    named = smear_kept.name(found, PredictedCamera(camera, 2.0))
    assert _template_recall(camera, named.marking_mask) > 0.95 > _template_recall(camera, found.unnamed.marking_mask)
    camera, image = _zoomed_frame(30.0)
    found = detector.find_markings(image)
    named = detector.name(found, PredictedCamera(camera, 2.0))
    assert np.array_equal(named.marking_mask, found.unnamed.marking_mask)
    assert np.array_equal(named.marking_points_px, found.unnamed.marking_points_px)


def test_a_blurred_frame_s_markings_are_found_without_a_camera_on_the_reduced_levels():
    """Frame 245 of ``bench placements --random --seed 3``: the ``blur`` look (a pan at speed, a soft lens), a 13 deg
    view from behind a goal. Its markings, smeared over about 10 px, fall under the working level's top-hat; found on
    the reduced levels with the gates eased by the frame's blur, they fix its camera and the true camera explains
    them (confidence 0.39 -> 0.83)."""
    from broadtrack_graph.benchmarks.placement_frames import draw_frame as draw_placement
    from broadtrack_graph.geometry.determinable import determinability
    from broadtrack_graph.reinit.confidence import confidence_parts
    from broadtrack_graph.synth.named_looks import LOOK_NAMES

    frame = draw_placement(3, 245, 1280, 720, list(LOOK_NAMES))
    truth = frame["drawn"].camera
    smear_kept = MotionBlurConfig(min_length_px=0)  # this rule alone, the smear not undone first (test_motion_blur)
    found = WeightFreeDetector(PITCH, WeightFreeConfig(motion_blur=smear_kept)).detect(frame["image"])
    unblurred = WeightFreeDetector(PITCH, WeightFreeConfig(blurred_from=float("inf"), motion_blur=smear_kept)).detect(
        frame["image"])
    assert determinability(truth, PITCH, explained_by=found.marking_mask).determinable
    assert not determinability(truth, PITCH, explained_by=unblurred.marking_mask).determinable
    curves = TemplateCurves(PITCH)
    assert confidence_parts(truth, found.marking_mask, curves, field_mask=found.field_mask)["confidence"] >= 0.7
    assert confidence_parts(truth, unblurred.marking_mask, curves, field_mask=unblurred.field_mask)["confidence"] < 0.5


def test_a_sharp_frame_s_markings_do_not_change_with_the_blur_rule():
    truth = _truth()
    image, _ = draw_frame(truth, seed=2)
    found = WeightFreeDetector(PITCH).find_markings(image)
    never = WeightFreeDetector(PITCH, WeightFreeConfig(blurred_from=float("inf"))).find_markings(image)
    np.testing.assert_array_equal(found.points_work_px, never.points_work_px)
    assert found.wide is not None  # kept for a wide marking the predicted camera may draw


def test_a_crowd_of_grass_coloured_specks_off_the_field_does_not_raise_the_ridge_threshold():
    """The top-hat's threshold adapts to the texture of the pitch's grass (``detect/ridges._threshold``): a stand of
    many-coloured blocks, a third of them green enough to pass as grass, is bright texture off the field. Measured on
    every grass-coloured pixel it raised the threshold over faint markings' contrast and they were lost."""
    truth = Camera.from_degrees(700.0, 0.0, -8.0, 84.0, 0.0, (0.0, 55.0, -12.0), W, H)  # half the frame is stand
    image, _ = draw_frame(truth, seed=3, line_grey=160)
    stand = np.all(image.astype(int) < 70, axis=2)  # the drawn stands (dark grey), not the pitch or its markings
    stand = cv2.erode(stand.astype(np.uint8), np.ones((31, 31), np.uint8)) > 0  # boards 15 px wide in front of it
    rng = np.random.default_rng(4)
    blocks = np.zeros((H // 3 + 1, W // 3 + 1, 3), np.uint8)
    blocks[..., 0] = rng.integers(0, 180, blocks.shape[:2])  # any hue, a third of them green
    blocks[..., 1] = rng.integers(120, 256, blocks.shape[:2])
    blocks[..., 2] = rng.integers(60, 256, blocks.shape[:2])
    crowd = cv2.cvtColor(np.repeat(np.repeat(blocks, 3, axis=0), 3, axis=1)[:H, :W], cv2.COLOR_HSV2BGR)
    image_with_crowd = np.where(stand[..., None], crowd, image)
    detector = WeightFreeDetector(PITCH, WeightFreeConfig(work_width_px=W))  # not reduced: the threshold adapts
    plain = detector.detect(image)
    with_crowd = detector.detect(image_with_crowd)
    assert stand.mean() > 0.4 and with_crowd.field_mask[stand].mean() < 0.05  # the crowd is not field
    assert _template_recall(truth, plain.marking_mask) > 0.8
    assert _template_recall(truth, with_crowd.marking_mask) > 0.9 * _template_recall(truth, plain.marking_mask)
