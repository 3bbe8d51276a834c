"""Court-model hypotheses: the homographies of line families, and their decomposition into cameras."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
from reinit_helpers import BOX_SEGMENTS, box_view, image_lines

from broadtrack_graph.detect.marking_structures import ImageLine
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.court_families import CourtLineConfig, line_families
from broadtrack_graph.reinit.court_lines import (
    cameras_from_homographies,
    equal_norms_in_range,
    focal_and_mismatch,
    homographies_from_maps,
    line_hypotheses,
    orthogonal_in_range,
    pitch_line_offsets,
    split_hypotheses,
)

PITCH = PitchTemplate()
W, H = 1280, 720


def test_pitch_line_offsets_are_the_painted_lines_of_each_direction():
    along_x, along_y = pitch_line_offsets(PITCH)
    assert np.allclose(along_x, [-34.0, -20.16, -9.16, 9.16, 20.16, 34.0], atol=0.01)
    assert np.allclose(along_y, [-52.5, -47.0, -36.0, 0.0, 36.0, 47.0, 52.5], atol=0.01)


def test_the_pairs_not_formed_hold_no_homography_the_gate_keeps():
    # The pairs of vanishing points and the pitch-line maps dropped before the homographies are formed must hold
    # none that focal_and_mismatch's gate keeps (f in range, axes orthogonal and of equal norm within the mismatch),
    # and the checks must drop most of the random ones.
    rng = np.random.default_rng(7)
    config = CourtLineConfig()
    f_lo, f_hi = (2.0 * v for v in config.focal_range_per_width)
    # Vanishing points of real cameras' pitch directions, disturbed, and random ones.
    cameras = [Camera.from_degrees(float(rng.uniform(500, 12000)), 0.0, float(rng.uniform(-180, 180)),
                                   float(rng.uniform(50, 88)), float(rng.uniform(-3, 3)), (0.0, 60.0, -20.0), W, H)
               for _ in range(150)]
    v_x, v_y = [], []
    for c in cameras:
        K_n = np.diag([c.focal_px / (W / 2.0), c.focal_px / (W / 2.0), 1.0])  # normalised coordinates: s = W / 2
        for axis, out in ((0, v_x), (1, v_y)):
            point = K_n @ c.R_cw[:, axis] + rng.normal(0.0, 0.05, 3)
            out.append(point / np.linalg.norm(point))
    v_x = np.vstack([v_x, rng.normal(size=(150, 3))])
    v_y = np.vstack([v_y, rng.normal(size=(150, 3))])
    v_x /= np.linalg.norm(v_x, axis=1, keepdims=True)
    v_y /= np.linalg.norm(v_y, axis=1, keepdims=True)
    # The maps' slopes spread over a factor of 3 either way of the ratio that makes the axes' norms equal.
    a_x = np.exp(rng.uniform(-3, 3, (300, 20))) * rng.choice([-1.0, 1.0], (300, 20))
    a_y = a_x[:, :1] * np.exp(rng.uniform(-1.1, 1.1, (300, 20))) * rng.choice([-1.0, 1.0], (300, 20))
    b_x, b_y = rng.normal(size=(300, 20)), rng.normal(size=(300, 20))
    H_n = homographies_from_maps(v_x[:, None, None], v_y[:, None, None], a_x[:, :, None], b_x[:, :, None],
                                 a_y[:, None, :], b_y[:, None, :])  # (300, 20, 20, 3, 3)
    focal_n, mismatch = focal_and_mismatch(H_n.reshape(-1, 3, 3))
    kept = (np.isfinite(focal_n) & (focal_n >= f_lo) & (focal_n <= f_hi)
            & (mismatch <= config.max_axis_mismatch)).reshape(300, 20, 20)
    orthogonal = orthogonal_in_range(v_x, v_y, f_lo, f_hi, config.max_axis_mismatch)  # (300,)
    equal = equal_norms_in_range(v_x, v_y, a_x, a_y, f_lo, f_hi, config.max_axis_mismatch)  # (300, 20, 20)
    formed = orthogonal[:, None, None] & equal
    assert kept.sum() > 100
    assert not np.any(kept & ~formed)
    assert formed.mean() < 0.5 and (~orthogonal).sum() > 30


def test_a_hypothesis_is_the_true_camera():
    truth = box_view()
    lines = image_lines(truth, BOX_SEGMENTS)
    support = np.array([line.support_px for line in lines])
    hypotheses = line_hypotheses(line_families(lines, (W, H))[0], support, PITCH, (W, H))
    assert len(hypotheses) > 1
    gap = np.linalg.norm(hypotheses.C_w - truth.position_m, axis=1)
    k = int(np.argmin(gap))
    assert gap[k] < 1e-6 * 100
    assert hypotheses.focal_n[k] * W / 2 == pytest.approx(truth.focal_px, rel=1e-6)
    assert np.allclose(hypotheses.angles_rad[k], [truth.pan_rad, truth.tilt_rad, truth.roll_rad], atol=1e-7)
    # Every hypothesis is a plausible broadcast camera: above the grass, off the playing area (or a few metres inside
    # it: a hypothesis's focal point is only as good as the markings it is decomposed from).
    C, slack = hypotheses.C_w, CourtLineConfig().inside_pitch_slack_m
    assert np.all(C[:, 2] <= -2.0) and np.all((np.abs(C[:, 0]) > 52.5 - slack) | (np.abs(C[:, 1]) > 34.0 - slack))


def test_a_line_that_joined_a_family_without_being_a_pitch_line_does_not_bend_the_others():
    # A narrow view: a board's edge nearly parallel to the penalty area's sides joins their family. Each hypothesis
    # takes its vanishing points from its own lines, so the one putting the true lines on the pitch is still exact.
    truth = Camera.from_degrees(4800.0, 0.0, -60.0, 80.0, 0.3, (85.0, 45.0, -20.0), W, H)
    segments = [((52.5, -9.0, 0.0), (52.5, 9.0, 0.0)), ((47.0, -9.16, 0.0), (47.0, 9.16, 0.0)),
                ((40.0, 20.16, 0.0), (52.0, 20.16, 0.0)), ((47.5, 9.16, 0.0), (52.0, 9.16, 0.0))]
    lines = image_lines(truth, segments)
    side = lines[2]  # a board's edge: the penalty area side turned by 0.6 deg about its middle
    turn = math.radians(0.6)
    rotation = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
    normal, direction = rotation @ side.normal, rotation @ side.direction
    board = ImageLine(normal, float(-normal @ (side.centre_px + [0.0, 40.0])), side.centre_px + [0.0, 40.0], direction,
                      side.extent_px, 2.0 * side.support_px)
    lines = lines + [board]
    support = np.array([line.support_px for line in lines])
    splits = line_families(lines, (W, H))
    family = [s for s in splits if s.family[4] >= 0 and s.family[4] == s.family[2] == s.family[3]]
    assert family, "the board's edge joins the sides' family"
    hypotheses = line_hypotheses(family[0], support, PITCH, (W, H))
    gap = np.linalg.norm(hypotheses.C_w - truth.position_m, axis=1)
    assert gap.min() < 1e-3
    assert hypotheses.focal_n[int(np.argmin(gap))] * W / 2 == pytest.approx(truth.focal_px, rel=1e-6)



def test_the_splits_formed_at_once_are_each_split_s_hypotheses_in_turn():
    # A board's edge beside the box's lines makes several splits; formed at once, the hypotheses are those of each
    # split one after the other, the same numbers in the same order, and max_hypotheses leaves out the splits after
    # the one that reaches it.
    truth = box_view()
    lines = image_lines(truth, BOX_SEGMENTS)
    side = lines[2]
    board = ImageLine(side.normal, float(-side.normal @ (side.centre_px + [0.0, 30.0])), side.centre_px + [0.0, 30.0],
                      side.direction, side.extent_px, 1.5 * side.support_px)
    lines = lines + [board]
    support = np.array([line.support_px for line in lines])
    splits = line_families(lines, (W, H))
    assert len(splits) >= 2
    each = [line_hypotheses(families, support, PITCH, (W, H)) for families in splits]
    together = split_hypotheses(splits, support, PITCH, (W, H))
    assert len(together) == sum(len(part) for part in each) > 0
    np.testing.assert_allclose(together.H_n, np.concatenate([part.H_n for part in each]), rtol=1e-12, atol=1e-12)
    np.testing.assert_array_equal(together.sign, np.concatenate([part.sign for part in each]))
    first_two = len(each[0]) + len(each[1])
    cut = split_hypotheses(splits, support, PITCH, (W, H), max_hypotheses=len(each[0]) + 1)
    assert len(cut) == first_two  # the second split brings the count over: it is kept, the rest are not
    assert len(split_hypotheses(splits, support, PITCH, (W, H), max_hypotheses=len(each[0]))) == len(each[0])
    assert len(split_hypotheses([], support, PITCH, (W, H))) == 0

def _normalised_homography(camera: Camera) -> np.ndarray:
    """The camera's ground-plane homography in the normalised image coordinates of the module."""
    K_n = np.diag([2 * camera.focal_px / W, 2 * camera.focal_px / W, 1.0])
    R, t = camera.R_cw, -camera.R_cw @ camera.position_m
    return K_n @ np.column_stack([R[:, 0], R[:, 1], t])


@pytest.mark.parametrize("scale", [1.0, -3.5])
def test_a_homography_decomposes_into_its_camera_whatever_its_scale(scale):
    truth = box_view()
    cameras = cameras_from_homographies(scale * _normalised_homography(truth)[None], (W, H), PITCH)
    assert len(cameras) == 1
    assert np.allclose(cameras.C_w[0], truth.position_m, atol=1e-6)
    assert cameras.focal_n[0] * W / 2 == pytest.approx(truth.focal_px, rel=1e-9)


def test_implausible_cameras_are_gated():
    main = Camera.from_degrees(1500.0, 0.0, 0.0, 75.0, 0.0, (0.0, 55.0, -15.0), W, H)
    on_pitch = main.replace(position_m=np.array([0.0, 20.0, -15.0]))
    rolled = main.replace(roll_rad=math.radians(25.0))
    mirrored = _normalised_homography(main) @ np.diag([1.0, -1.0, 1.0])  # the pitch seen in a mirror
    upside_down = main.replace(roll_rad=math.pi)  # decomposes as pan + 180 deg, tilt -75 deg, roll 0
    stacked = np.stack([_normalised_homography(main), _normalised_homography(on_pitch),
                        _normalised_homography(rolled), mirrored, _normalised_homography(upside_down)])
    kept = cameras_from_homographies(stacked, (W, H), PITCH)
    assert len(kept) == 1 and np.allclose(kept.C_w[0], main.position_m, atol=1e-6)


def test_a_homography_of_determinant_zero_is_no_camera_and_raises_no_warning():
    # Its third column in the plane of the first two (the horizon through the image centre): the focal length and the
    # axes' mismatch are a camera's, but no camera draws it.
    H_n = _normalised_homography(box_view())
    flat = H_n.copy()
    flat[:, 2] = 0.3 * H_n[:, 0] - 0.2 * H_n[:, 1]
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        kept = cameras_from_homographies(np.stack([flat, H_n]), (W, H), PITCH)
    assert len(kept) == 1 and np.allclose(kept.C_w[0], box_view().position_m, atol=1e-6)


def test_a_hypothesis_a_few_metres_inside_the_touchline_is_kept_for_the_fit():
    # A camera at a touchline decomposed from an arc's ellipse can come out metres inside it: kept for the fit (whose
    # camera must then stand off the pitch, reinit.court), while one deep inside the pitch is not.
    slack = CourtLineConfig().inside_pitch_slack_m
    near = Camera.from_degrees(2500.0, 0.0, 180.0, 60.0, 0.0, (-20.0, -(34.0 - 0.5 * slack), -40.0), W, H)
    deep = near.replace(position_m=np.array([-20.0, -(34.0 - 2.0 * slack), -40.0]))
    kept = cameras_from_homographies(np.stack([_normalised_homography(near), _normalised_homography(deep)]), (W, H),
                                     PITCH)
    assert len(kept) == 1 and np.allclose(kept.C_w[0], near.position_m, atol=1e-6)
