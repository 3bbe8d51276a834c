"""Weight-free re-initialisation from the marking map: rendered hard frames and the real broadcast frame."""

from __future__ import annotations

import numpy as np
import pytest
from conftest import SHARED_DATA
from reinit_helpers import median_template_error_px as _median_template_error_px

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves
from broadtrack_graph.reinit.mask import reinit_from_mask

PITCH = PitchTemplate()
CURVES = TemplateCurves(PITCH)
REAL_FRAME = SHARED_DATA / "real-frames" / "broadcast-frame-1073x603.png"


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
    truth, det = hard_frames[which]
    assert truth.focal_px > 2.2 * 1920  # about 25 deg of field of view: a coarse pan/tilt grid misses it
    # The default tripod guesses, not the true focal point (which is ~0.3 m from the main one here).
    result = reinit_from_mask(det.marking_mask, det.marking_points_px, (1920, 1080), PITCH, curves=CURVES,
                              field_mask=det.field_mask)
    assert result.camera is not None
    assert 0.0 < _median_template_error_px(result.camera, truth) < 2.0
    assert 0.7 < result.score.jaccard <= 1.0


def test_label_and_fit_rounds_before_the_last_stop_early_and_land_where_fully_converged_rounds_do(main_frame,
                                                                                                 monkeypatch):
    from dataclasses import replace

    from broadtrack_graph.reinit import mask
    from broadtrack_graph.reinit.mask import fit_points, refine_on_map
    from broadtrack_graph.reinit.mask_config import MaskSearchConfig

    truth, det = main_frame
    config = MaskSearchConfig()
    points = fit_points(det.marking_points_px, config)
    # A hypothesis as a search makes one: roll and k1 0, pan, tilt and f a little off, at the right focal point.
    start = truth.replace(focal_px=0.95 * truth.focal_px, pan_rad=truth.pan_rad - np.radians(0.6),
                          tilt_rad=truth.tilt_rad + np.radians(0.4), roll_rad=0.0, k1=0.0)
    assert _median_template_error_px(start, truth) > 20.0
    iterations = []
    fit = mask.fit_camera_to_lines

    def counted(*args, **kwargs):
        result = fit(*args, **kwargs)
        iterations.append(result.iterations)
        return result

    monkeypatch.setattr(mask, "fit_camera_to_lines", counted)
    early_total = full_total = 0
    for schedule in (config.schedule, config.wide_schedule):
        assert schedule.early_round_min_relative_decrease > 1e-5
        converged = replace(schedule, early_round_min_relative_decrease=1e-5)  # every round stops as the last does
        iterations.clear()
        early = refine_on_map(start, points, truth.position_m, CURVES, config, schedule)
        early_iterations = sum(iterations)
        iterations.clear()
        full = refine_on_map(start, points, truth.position_m, CURVES, config, converged)
        assert early_iterations < sum(iterations)
        early_total, full_total = early_total + early_iterations, full_total + sum(iterations)
        assert _median_template_error_px(full, truth) < 1.0
        assert _median_template_error_px(early, full) < 0.1  # under a tenth of a pixel: the same place
    assert early_total < 0.85 * full_total


def test_reinit_from_mask_on_the_real_broadcast_frame():
    """The real frame is a main-camera view of the right penalty area from far back (a stadium with a track)."""
    import cv2

    from broadtrack_graph.detect.weightfree import WeightFreeDetector

    if not REAL_FRAME.exists():
        pytest.skip(f"real frame not found at {REAL_FRAME} (only present beside the CI clone)")
    image = cv2.imread(str(REAL_FRAME))
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


def test_reinit_from_mask_finds_a_lower_league_camera_at_the_near_positions():
    from broadtrack_graph.detect.weightfree import WeightFreeDetector
    from broadtrack_graph.reinit.positions import NEAR_MAIN_POSITIONS_W
    from broadtrack_graph.synth.clip import render_clip
    from broadtrack_graph.synth.motion import generate_camera_track

    # The `low` preset: 7 m behind the touchline, 5.5 m up, none of the default or far tripod guesses near it.
    track = generate_camera_track("low", 1, 1920, 1080, seed=0)
    frame = render_clip("low", 1, 1920, 1080, seed=0, cameras=[track.cameras[0]]).frames[0]
    det = WeightFreeDetector(PITCH).detect(frame.image)
    args = (det.marking_mask, det.marking_points_px, (1920, 1080), PITCH)
    # Searched at each low gantry position on its own (positions given: track --reinit-position).
    near = [reinit_from_mask(*args, positions_w=(p,), curves=CURVES, field_mask=det.field_mask)
            for p in NEAR_MAIN_POSITIONS_W]
    found = max((r for r in near if r.camera is not None), key=lambda r: r.score.jaccard)
    assert found.score.jaccard > 0.6
    assert _median_template_error_px(found.camera, frame.camera) < 5.0
    assert np.linalg.norm(found.camera.position_m - frame.camera.position_m) < 1.5
    # The default positions alone settle on a wrong camera, under what a new chain needs (TrackingConfig's
    # confidence_threshold + reinit_switch_margin, 0.6; 0.52 here: 3.7 deg wide, a line along the boards' base).
    default = reinit_from_mask(*args, curves=CURVES, field_mask=det.field_mask)
    assert default.camera is None or default.score.jaccard < 0.6
    assert default.camera is None or _median_template_error_px(default.camera, frame.camera) > 20.0


def test_a_frame_s_stages_share_its_map_structures(hard_frames):
    """The marking map's structures (scorers, straight markings, ellipses) are built once a frame: a later stage of
    the same frame and settings reuses them, and a new map or a setting the scorers read builds its own."""
    from broadtrack_graph.reinit.mask import map_structures
    from broadtrack_graph.reinit.mask_config import MaskSearchConfig

    _, det = hard_frames[0]
    usual = map_structures(det.marking_mask, det.marking_points_px, (1920, 1080), PITCH, MaskSearchConfig())
    again = map_structures(det.marking_mask, det.marking_points_px, (1920, 1080), PITCH, MaskSearchConfig())
    assert again is usual
    _, other = hard_frames[1]
    assert map_structures(other.marking_mask, other.marking_points_px, (1920, 1080), PITCH,
                          MaskSearchConfig()) is not usual
    wider = MaskSearchConfig(score_hit_px=2 * MaskSearchConfig().score_hit_px)  # a setting the scorers read
    assert map_structures(det.marking_mask, det.marking_points_px, (1920, 1080), PITCH, wider) is not usual


def test_points_are_named_by_the_nearest_class_projected_in_view():
    from reinit_helpers import labelled_lines, reference_camera

    from broadtrack_graph.geometry.template import closest_on_polyline
    from broadtrack_graph.reinit.mask import label_points_by_camera

    camera = reference_camera()
    lines = labelled_lines(camera, np.random.default_rng(4), noise_px=1.0)
    points = np.vstack(list(lines.values()) + [[[5.0, 5.0], [950.0, 20.0]]])  # two points near no marking
    named = label_points_by_camera(camera, points, CURVES, gate_px=6.0)
    # The reference: each ground class projected on its own, a point named by the nearest one within the gate.
    distances = np.full((len(points), len(CURVES.samples_w)), np.inf)
    names = list(CURVES.samples_w)
    for j, name in enumerate(names):
        if not PITCH.is_on_ground(name):
            continue
        uv, front = camera.project(CURVES.samples_w[name])
        ok = front & camera.in_image(uv)
        if (ok[:-1] & ok[1:]).any():
            distances[:, j] = closest_on_polyline(points, uv, ok[:-1] & ok[1:])[2]
    nearest, within = np.argmin(distances, axis=1), distances.min(axis=1) < 6.0
    expected = {name: points[within & (nearest == j)] for j, name in enumerate(names)}
    assert named.keys() == {name for name, p in expected.items() if len(p) >= 3}
    for name, named_points in named.items():
        np.testing.assert_array_equal(named_points, expected[name])
    assert len(named) >= 4 and sum(map(len, named.values())) <= len(points) - 2
