"""The court model's last steps: the twin rule, the fit kept and the judging of a fitted camera."""

from __future__ import annotations

import math

import numpy as np
import pytest

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.court_config import CourtConfig
from broadtrack_graph.reinit.court_fit import Fit, judged, kept_camera, main_side, off_the_pitch, twin_camera
from broadtrack_graph.reinit.frame import plausible_position

PITCH = PitchTemplate()
W, H = 960, 540


def _aimed(position, target, hfov_deg: float) -> Camera:
    from broadtrack_graph.geometry.aim import aim_angles

    pan, tilt = aim_angles(np.asarray(position, float), np.asarray(target, float))
    return Camera(W / 2 / math.tan(math.radians(hfov_deg) / 2), 0.01, pan, tilt, 0.004, position, W, H)


def test_the_twin_sees_the_half_turned_pitch_exactly_as_the_camera_sees_the_pitch():
    camera = _aimed((12.0, -48.0, -14.0), (25.0, -5.0, 0.0), 32.0)
    twin = twin_camera(camera)
    points = np.array([[x, y, 0.0] for x in (10.0, 25.0, 40.0) for y in (-20.0, -5.0, 10.0)])
    uv, front = camera.project(points)
    uv_twin, front_twin = twin.project(points * np.array([-1.0, -1.0, 1.0]))
    assert front.all() and front_twin.all()
    np.testing.assert_allclose(uv_twin, uv, atol=1e-6)
    np.testing.assert_allclose(twin_camera(twin).position_m, camera.position_m)


def test_the_main_side_is_kept_and_on_the_halfway_axis_the_left_end():
    tie = CourtConfig().twin_tie_m
    near = _aimed((5.0, 50.0, -15.0), (0.0, 0.0, 0.0), 40.0)
    assert main_side(near, tie) is near
    far = twin_camera(near)
    assert main_side(far, tie).position_m[1] > 0
    behind_right = _aimed((70.0, 0.5 * tie, -20.0), (30.0, 0.0, 0.0), 40.0)  # on the halfway line's axis, x > 0
    kept = main_side(behind_right, tie)
    assert kept.position_m[0] < 0 and np.isclose(kept.position_m[0], -behind_right.position_m[0])


def test_a_judged_camera_carries_the_confidence_it_was_given_and_its_twin():
    camera = _aimed((0.0, 55.0, -15.0), (0.0, 0.0, 0.0), 40.0)
    shown = np.ones((H, W), bool)  # every marking in view explained: the camera is fixed with constraints to spare
    asked = []

    def confidence_of(c):
        asked.append(c)
        return 0.87

    result = judged(camera, shown, PITCH, CourtConfig(), confidence_of)
    assert result.camera is camera and result.score.jaccard == 0.87 and asked == [camera]
    np.testing.assert_allclose(result.twin.position_m, twin_camera(camera).position_m)


def test_a_camera_on_the_pitch_or_fixed_by_nothing_is_not_returned():
    on_pitch = _aimed((10.0, 20.0, -15.0), (30.0, 0.0, 0.0), 40.0)
    result = judged(on_pitch, np.ones((H, W), bool), PITCH, CourtConfig(), lambda c: 1.0)
    assert result.camera is None and "not a broadcast camera's" in result.reason
    camera = _aimed((0.0, 55.0, -15.0), (0.0, 0.0, 0.0), 40.0)
    result = judged(camera, np.zeros((H, W), bool), PITCH, CourtConfig(), lambda c: 1.0)
    assert result.camera is None and "do not fix it" in result.reason
    assert judged(None, np.zeros((H, W), bool), PITCH, CourtConfig(), lambda c: 1.0).camera is None


def test_the_best_scoring_fit_is_kept_unless_another_is_more_confident_by_the_margin():
    config = CourtConfig()
    a = _aimed((0.0, 60.0, -20.0), (10.0, 0.0, 0.0), 30.0)
    b = _aimed((0.0, 62.0, -21.0), (10.0, 0.0, 0.0), 30.0)
    assert kept_camera([Fit(0, 0.8, 0.80, a), Fit(1, 0.7, 0.85, b)], PITCH, config) is a
    assert kept_camera([Fit(0, 0.8, 0.80, a), Fit(1, 0.7, 0.80 + config.confidence_margin, b)], PITCH, config) is b
    assert kept_camera([], PITCH, config) is None


def test_a_fit_slid_out_of_the_stadium_is_neither_kept_over_one_within_it_nor_returned():
    # A narrow view's fits from different depths along its line of sight: the one scoring best slid back to 190 m from
    # the centre spot, where no broadcast camera stands (a tenth of a pixel better on the map, 1.6 px off the truth).
    config = CourtConfig()
    within = _aimed((-100.0, 10.0, -40.0), (-30.0, 0.0, 0.0), 12.0)
    far = _aimed((-188.0, 24.0, -75.0), (-30.0, 0.0, 0.0), 6.5)
    assert plausible_position(within.position_m, PITCH) and not plausible_position(far.position_m, PITCH)
    assert kept_camera([Fit(0, 0.80, 0.70, far), Fit(1, 0.79, 0.95, within)], PITCH, config) is within
    assert judged(far, np.zeros((H, W), bool), PITCH, config, lambda camera: 0.95).reason.endswith(
        "out of the stadium)")


def test_a_fit_standing_on_the_playing_area_is_not_kept_over_one_standing_where_a_camera_can():
    # Fits laying the same image from different depths along the line of sight (a circle and a line fix a camera
    # exactly): the one scoring best stands 36 m above the pitch.
    config = CourtConfig()
    off = _aimed((0.0, 60.0, -20.0), (10.0, 0.0, 0.0), 30.0)
    over = _aimed((5.0, 25.0, -36.0), (10.0, 0.0, 0.0), 30.0)
    assert kept_camera([Fit(0, 0.74, 0.95, over), Fit(1, 0.72, 0.95, off)], PITCH, config) is off
    # ... and when every fit stands there, the best is kept (and judged: not returned)
    assert kept_camera([Fit(0, 0.74, 0.95, over)], PITCH, config) is over
    assert judged(over, np.zeros((H, W), bool), PITCH, config, lambda camera: 0.95).camera is None


def test_a_camera_on_the_pitch_is_moved_back_along_its_line_of_sight_to_just_past_the_pitchs_edge():
    """A narrow view from 12 m up over the playing area (where a fit of a nearly affine view can slide): moved back
    along its optical axis until it stands 0.5 m past the nearest edge it crosses, the ground point it looks at still
    at the image centre and its surroundings drawn about the same size."""
    camera = _aimed((-20.0, 25.0, -12.0), (-30.0, -10.0, 0.0), 15.0)
    assert not plausible_position(camera.position_m, PITCH)
    moved = off_the_pitch(camera, PITCH)
    assert plausible_position(moved.position_m, PITCH)
    half_width = PITCH.dimensions.width_m / 2
    assert abs(moved.position_m[1]) == pytest.approx(half_width + 0.5, abs=1e-6)  # it leaves by the touchline
    assert abs(moved.position_m[0]) < PITCH.dimensions.length_m / 2
    look_at = np.array([-30.0, -10.0, 0.0])
    np.testing.assert_allclose(moved.project(look_at[None])[0][0], [W / 2, H / 2], atol=1e-6)
    step = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])  # a metre either way of it: about as many pixels as before
    size = [np.linalg.norm(c.project(look_at + step)[0] - c.project(look_at[None])[0], axis=1) for c in (camera, moved)]
    np.testing.assert_allclose(size[1], size[0], rtol=0.05)
    assert moved.focal_px > camera.focal_px
    standing = _aimed((0.0, 50.0, -15.0), (0.0, 0.0, 0.0), 40.0)
    assert off_the_pitch(standing, PITCH) is standing  # already where a camera can stand


def test_a_camera_under_the_grass_or_looking_above_the_horizon_is_not_moved():
    under = _aimed((0.0, 10.0, 3.0), (0.0, 0.0, 0.0), 20.0)
    assert off_the_pitch(under, PITCH) is None
    upward = Camera(1000.0, 0.0, 0.0, math.radians(100.0), 0.0, np.array([0.0, 10.0, -10.0]), W, H)
    assert off_the_pitch(upward, PITCH) is None
