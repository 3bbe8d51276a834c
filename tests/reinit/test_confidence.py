"""The confidence of a camera against a marking map and a field map drawn here."""

from __future__ import annotations

from dataclasses import replace

import cv2
import numpy as np
import pytest

from broadtrack_graph.detect.motion_blur import MotionBlur, motion_kernel
from broadtrack_graph.detect.smeared_markings import SmearedImage
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves, project_template
from broadtrack_graph.reinit.confidence import (
    ConfidenceConfig,
    camera_confidence,
    confidence_parts,
    field_coverage,
    recall_across_motion,
    smeared_contrast,
)
from broadtrack_graph.reinit.frame_maps import inside_field_edge
from broadtrack_graph.reinit.template_reach import found_by_map_value, found_by_paint_width

W, H = 960, 540
PITCH = PitchTemplate()
CURVES = TemplateCurves(PITCH)
TRUTH = Camera.from_degrees(1100.0, 0.0, 5.0, 76.0, 0.0, (0.0, 55.0, -12.0), W, H)


def _maps(camera, grass_margin_m=3.0):
    """The ground markings drawn 2 px wide as the camera sees them, and the grass: the pitch plus a margin."""
    marks = np.zeros((H, W), np.uint8)
    for name, pts in PITCH.sample_uniform(0.1).items():
        if PITCH.is_on_ground(name):
            uv, front = camera.project(pts)
            uv = uv[front & np.all(np.abs(uv) < 1e4, axis=1)]
            if len(uv) >= 2:
                cv2.polylines(marks, [np.round(uv).astype(np.int32)], False, 1, 2)
    rows, cols = np.mgrid[0:H, 0:W]
    ground, hits = camera.ground_intersection(np.column_stack([cols.ravel(), rows.ravel()]).astype(float))
    with np.errstate(invalid="ignore"):
        grass = hits & (np.abs(ground[:, 0]) < 52.5 + grass_margin_m) & (np.abs(ground[:, 1]) < 34.0 + grass_margin_m)
    return marks > 0, grass.reshape(H, W)


def test_the_true_camera_explains_the_map_and_all_the_grass():
    marks, grass = _maps(TRUTH)
    parts = confidence_parts(TRUTH, marks, CURVES, field_mask=grass)
    assert parts["field_coverage"] == pytest.approx(1.0)
    assert parts["confidence"] > 0.95
    assert field_coverage(TRUTH, grass, PITCH) == pytest.approx(1.0)
    assert field_coverage(TRUTH, np.zeros_like(grass), PITCH) == 1.0  # no grass in view: nothing to explain


def test_specks_of_grass_texture_do_not_lower_the_precision():
    # Grass texture seen at a grazing angle passes the detector's ridge test in specks a few pixels long, scattered
    # over the field: no camera explains them. The precision reads only pieces of the map at least
    # min_piece_length_px long; the recall, every marking pixel.
    marks, grass = _maps(TRUTH)
    rng = np.random.default_rng(7)
    specked = marks.copy()
    rows, cols = np.nonzero(grass & (cv2.dilate(marks.astype(np.uint8), np.ones((9, 9), np.uint8)) == 0))
    for k in rng.choice(len(rows), 900, replace=False):
        specked[rows[k], cols[k]:cols[k] + rng.integers(3, 8)] = True  # a horizontal streak 3-7 px long
    clean = confidence_parts(TRUTH, marks, CURVES, field_mask=grass)
    parts = confidence_parts(TRUTH, specked, CURVES, field_mask=grass)
    every_piece = confidence_parts(TRUTH, specked, CURVES, ConfidenceConfig(min_piece_length_px=0.0), field_mask=grass)
    assert every_piece["precision"] < 0.65 * clean["precision"]  # the specks are 40 % of the map's pixels
    assert parts["precision"] > 0.95 * clean["precision"] and parts["confidence"] > 0.95
    assert parts["recall"] == pytest.approx(every_piece["recall"])
    # A camera 20 px off stays far under it: the markings it misses are long pieces (the specks it lands on raise
    # its recall a little, as they did before).
    off = TRUTH.replace(pan_rad=TRUTH.pan_rad + 20.0 / TRUTH.focal_px)
    off_specked = confidence_parts(off, specked, CURVES, field_mask=grass)["confidence"]
    assert off_specked < confidence_parts(off, marks, CURVES, field_mask=grass)["confidence"] + 0.05
    assert off_specked < parts["confidence"] - 0.3


def test_a_camera_that_leaves_the_grass_off_its_pitch_is_scaled_down():
    # A camera looking over the far touchline at grass that goes on (a field map of the whole image): it
    # explains every marking, but the grass in the upper part of the image lies far off its pitch.
    over = TRUTH.replace(tilt_rad=TRUTH.tilt_rad + np.radians(6.0), focal_px=1.5 * TRUTH.focal_px)
    marks, _ = _maps(over)
    grass = np.ones((H, W), bool)
    coverage = field_coverage(over, grass, PITCH)
    assert 0.1 < coverage < 0.6
    plain = confidence_parts(over, marks, CURVES, ConfidenceConfig(min_field_coverage=0.0), field_mask=grass)
    scaled = confidence_parts(over, marks, CURVES, field_mask=grass)
    assert plain["confidence"] > 0.9
    assert scaled["field_coverage"] == pytest.approx(coverage)
    assert scaled["confidence"] == pytest.approx(plain["confidence"] * coverage / 0.7, rel=1e-6)
    # The grass within field_margin_m of the lines counts as explained.
    _, grass_wide = _maps(TRUTH, grass_margin_m=8.0)
    assert field_coverage(TRUTH, grass_wide, PITCH, margin_m=10.0) == pytest.approx(1.0)
    assert field_coverage(TRUTH, grass_wide, PITCH, margin_m=2.0) < 1.0


def test_markings_in_the_band_along_the_fields_edge_are_not_expected():
    # Boards right behind the lines: the field ends at the touch and goal lines, and the detector keeps no marking
    # within its boundary margin of that edge (the boards' bright base), so the lines along it are not found.
    marks, grass = _maps(TRUTH, grass_margin_m=0.0)
    marks = marks & inside_field_edge(grass, 5)
    compared = confidence_parts(TRUTH, marks, CURVES, field_mask=grass)
    expecting_the_band = confidence_parts(TRUTH, marks, CURVES, ConfidenceConfig(field_edge_px=0), field_mask=grass)
    assert compared["recall"] > 0.97 and compared["confidence"] > 0.95
    assert expecting_the_band["recall"] < 0.85
    assert compared["template_samples"] < expecting_the_band["template_samples"]
    # A camera off by 20 px is not helped by it.
    off = TRUTH.replace(pan_rad=TRUTH.pan_rad + 20.0 / TRUTH.focal_px)
    assert confidence_parts(off, marks, CURVES, field_mask=grass)["confidence"] < 0.5


def test_markings_found_on_lines_too_thin_to_expect_are_still_explained():
    # A camera high behind the pitch: most of its 12 cm lines project under min_line_width_px, so recall expects few
    # of them, but the markings the detector does find on them are the template's and explain the map.
    far = Camera.from_degrees(800.0, 0.0, 0.0, 66.0, 0.0, (0.0, 80.0, -35.0), W, H)
    marks, grass = _maps(far)
    parts = confidence_parts(far, marks, CURVES, field_mask=grass)
    everything = confidence_parts(far, marks, CURVES, ConfidenceConfig(min_line_width_px=0.0), field_mask=grass)
    assert parts["template_samples"] < 0.5 * everything["template_samples"]  # most lines are too thin to expect
    assert parts["precision"] == pytest.approx(everything["precision"])  # ... yet every marking found is explained
    assert parts["precision"] > 0.9
    # A camera off by a few metres explains far less of the same map.
    off = far.replace(position_m=np.asarray(far.position_m) + [6.0, 0.0, 0.0])
    assert confidence_parts(off, marks, CURVES, field_mask=grass)["precision"] < 0.6


def test_a_sweep_is_checked_only_by_the_markings_that_cross_it():
    # The true camera's map with only the markings along the touchlines left (across the image, seen from the main
    # stand): a sideways sweep is crossed by none of them; an up-and-down one is crossed by them (and by the flat
    # parts of the circles, which are not drawn).
    camera = TRUTH
    marks = np.zeros((H, W), np.uint8)
    for name, pts in PITCH.sample_uniform(0.1).items():
        element = PITCH.elements[name]
        across_image = hasattr(element, "start_w") and abs(element.end_w[1] - element.start_w[1]) < 1e-6
        if PITCH.is_on_ground(name) and across_image:
            uv, front = camera.project(pts)
            uv = uv[front & np.all(np.abs(uv) < 1e4, axis=1)]
            if len(uv) >= 2:
                cv2.polylines(marks, [np.round(uv).astype(np.int32)], False, 1, 2)
    marks = marks > 0
    sideways, count = recall_across_motion(camera, marks, np.array([60.0, 0.0]), CURVES)
    assert count > 300 and sideways < 0.1
    downwards, count = recall_across_motion(camera, marks, np.array([0.0, 60.0]), CURVES)
    assert count > 300 and downwards > 0.4
    # With every marking found, a sideways sweep is checked too; no motion: nothing to say.
    full, _ = _maps(camera)
    assert recall_across_motion(camera, full, np.array([60.0, 0.0]), CURVES)[0] > 0.9
    assert recall_across_motion(camera, full, np.zeros(2), CURVES) == (0.0, 0)


def test_a_view_whose_lines_are_all_too_thin_to_expect_is_judged_on_the_thin_lines_the_map_shows():
    # A wide camera far behind the touchline: every 12 cm line projects under min_line_width_px. Where the detector
    # finds them anyway, the recall counts them, found and missed; where it finds little of them, they count not at all.
    wide = Camera.from_degrees(700.0, 0.0, 0.0, 70.0, 0.0, (0.0, 100.0, -40.0), W, H)
    marks, grass = _maps(wide)
    parts = confidence_parts(wide, marks, CURVES, field_mask=grass)
    assert parts["template_samples"] < 50  # nothing wide enough to expect
    assert parts["recall"] > 0.95 and parts["confidence"] > 0.9
    never = confidence_parts(wide, marks, CURVES, ConfidenceConfig(thin_found_share=1.0), field_mask=grass)
    assert never["confidence"] < 0.3  # judged on the wide template alone: nothing to find
    # Only the left third of the map kept: too little of the thin template found for it to count.
    part = marks.copy()
    part[:, W // 3:] = False
    kept = confidence_parts(wide, part, CURVES, field_mask=grass)
    alone = confidence_parts(wide, part, CURVES, ConfidenceConfig(thin_found_share=1.0), field_mask=grass)
    assert kept["recall"] == pytest.approx(alone["recall"])


def test_the_far_lines_across_a_low_cameras_view_are_not_expected():
    # A camera 6 m up behind the left goal: the halfway line and the lines beyond it lie across its view at a grazing
    # angle, their paint foreshortened to a fraction of a pixel however large their scale f / depth. The map holds
    # the markings whose paint is at least 0.15 px wide (what the detector finds): the true camera is not marked
    # down for the others; a camera 20 px off still is.
    low = Camera.from_degrees(2000.0, 0.0, 90.0, 84.0, 0.0, (-62.0, 0.0, -6.0), W, H)
    template = project_template(low, CURVES, W, H, 1.0, paint_widths=True)
    painted = template.uv_px[template.paint_width_px >= 0.15]
    marks = np.zeros((H, W), np.uint8)
    marks[np.round(painted[:, 1]).astype(int), np.round(painted[:, 0]).astype(int)] = 1
    marks = cv2.dilate(marks, np.ones((2, 2), np.uint8)) > 0
    _, grass = _maps(low)
    seen = confidence_parts(low, marks, CURVES, field_mask=grass)
    expecting_all = confidence_parts(low, marks, CURVES, ConfidenceConfig(min_paint_width_px=0.0), field_mask=grass)
    assert seen["recall"] > 0.95 and seen["confidence"] > 0.9
    assert expecting_all["recall"] < seen["recall"] - 0.1
    assert seen["template_samples"] < expecting_all["template_samples"]
    off = low.replace(tilt_rad=low.tilt_rad + 20.0 / low.focal_px)
    assert confidence_parts(off, marks, CURVES, field_mask=grass)["confidence"] < 0.3
    # What the width is read from: the samples by painted width, and how many of them the map shows.
    samples, found = found_by_paint_width(low, marks, np.array([0.0, 0.15, np.inf]), CURVES, field_mask=grass)
    assert samples[0] > 100 and found[0] < 0.5 * samples[0]
    assert samples[1] > 1000 and found[1] == samples[1]
    # The same samples by a map's value along them: its left half 5, its right half 30 (any map size of the aspect).
    values = np.full((H // 2, W // 2), 5, np.uint8)
    values[:, W // 4:] = 30
    edges = np.array([0.0, 10.0, np.inf])
    by_value, found_by_value = found_by_map_value(low, marks, values, edges, CURVES, field_mask=grass)
    by_width, found_by_width = found_by_paint_width(low, marks, np.array([0.15, np.inf]), CURVES, field_mask=grass)
    expected = template.uv_px[(template.paint_width_px >= 0.15) & (template.uv_px[:, 0] < W / 2 - 4)]
    assert by_value.sum() == by_width.sum()  # every expected sample (paint 0.15 px wide), in one bin or the other
    assert by_value[0] > 100 and by_value[1] > 100
    assert abs(by_value[0] - len(expected)) < 0.15 * len(expected)  # the left half's, about
    assert found_by_value.sum() == found_by_width.sum()


def _smear(length_px: float, angle_deg: float) -> MotionBlur:
    return MotionBlur(length_px, angle_deg, -0.4, 0.3)


def test_a_smear_leaves_a_marking_across_it_its_painted_width_over_the_smear_across_it():
    # One line along x, one along y and one at 45 deg, 2 px of paint each, under a 20 px smear along x: the line along
    # it keeps its contrast, the line across it 2 / 20, the diagonal one 2 / (20 sin 45 deg); a lone sample (no
    # neighbour of its class: no direction) is kept whole.
    t = np.arange(50.0)
    uv = np.concatenate([np.column_stack([t, 0 * t]), np.column_stack([0 * t, t]), np.column_stack([t, t]),
                         [[300.0, 300.0]]])
    classes = np.repeat([0, 1, 2, 3], [50, 50, 50, 1])
    share = smeared_contrast(uv, classes, np.full(len(uv), 2.0), _smear(20.0, 0.0))
    assert np.allclose(share[:50], 1.0)
    assert np.allclose(share[50:100], 0.1)
    assert np.allclose(share[100:150], 2.0 / (20.0 * np.sin(np.radians(45.0))))
    assert share[150] == 1.0
    # A smear no longer than the paint is wide leaves it whole; the angle is a direction (0 and 180 deg alike).
    assert np.allclose(smeared_contrast(uv, classes, np.full(len(uv), 2.0), _smear(1.5, 90.0)), 1.0)
    assert np.allclose(share, smeared_contrast(uv, classes, np.full(len(uv), 2.0), _smear(20.0, 180.0)))


def test_the_markings_a_smear_wipes_out_are_not_expected_and_the_ones_along_it_still_are():
    # The true camera's map with the markings across a sideways smear gone (as a fast pan leaves it): judged as on a
    # sharp frame, its recall falls; told the frame's smear, only the markings along it are expected and it is as
    # confident as on the whole map. A camera off the truth across the smear is not helped: the lines along the smear
    # place it.
    camera = TRUTH
    full, grass = _maps(camera)
    template = project_template(camera, CURVES, W, H, 1.0, paint_widths=True)
    smear = _smear(60.0, 0.0)
    wiped = smeared_contrast(template.uv_px, template.class_index, template.paint_width_px, smear) < 0.075
    gone = np.zeros((H, W), np.uint8)
    gone[np.round(template.uv_px[wiped, 1]).astype(int), np.round(template.uv_px[wiped, 0]).astype(int)] = 1
    marks = full & ~(cv2.dilate(gone, np.ones((7, 7), np.uint8)) > 0)
    assert wiped.sum() > 200 and marks.sum() > 0.3 * full.sum()
    sharp = camera_confidence(camera, marks, CURVES, field_mask=grass)
    told = camera_confidence(camera, marks, CURVES, field_mask=grass, motion_blur=smear)
    whole = camera_confidence(camera, full, CURVES, field_mask=grass)
    assert sharp < 0.75 and told > 0.9 and told == pytest.approx(whole, abs=0.05)
    assert camera_confidence(camera, marks, CURVES, ConfidenceConfig(min_smeared_contrast=0.0), field_mask=grass,
                             motion_blur=smear) == pytest.approx(sharp)
    # The blur's length is in the camera's frame pixels: the same smear in a 1920 px frame is twice as long.
    big = camera.rescaled(2 * W, 2 * H)
    assert camera_confidence(big, marks, CURVES, field_mask=grass, motion_blur=_smear(120.0, 0.0)) == \
        pytest.approx(told, abs=0.01)
    off = camera.replace(tilt_rad=camera.tilt_rad + 15.0 / camera.focal_px)
    assert camera_confidence(off, marks, CURVES, field_mask=grass, motion_blur=smear) < 0.5


def test_the_markings_across_a_smear_are_asked_of_the_smeared_image_where_the_detector_keeps_it():
    # The true camera's markings drawn 2 px wide, 120 levels over the grass, then smeared 60 px along x (a fast pan):
    # the marking map keeps only those the smear leaves 0.075 of their contrast or more. Asked of the smeared image,
    # the markings across the smear with less (0.05 or more) show as their bands for the true camera; a camera off
    # across the smear by more than half a band (40 px: its lines along the smear still on the map's) lays them on
    # grass or a band's edge.
    camera = TRUTH
    full, grass = _maps(camera)
    template = project_template(camera, CURVES, W, H, 1.0, paint_widths=True)
    blur = _smear(60.0, 0.0)
    share = smeared_contrast(template.uv_px, template.class_index, template.paint_width_px, blur)
    wiped = np.zeros((H, W), np.uint8)
    gone = np.round(template.uv_px[share < 0.075]).astype(int)
    wiped[gone[:, 1], gone[:, 0]] = 1
    marks = full & ~(cv2.dilate(wiped, np.ones((7, 7), np.uint8)) > 0)
    assert ((share >= 0.05) & (share < 0.075)).sum() > 200
    painted = np.where(full, 200.0, 80.0).astype(np.float32)
    smeared = cv2.filter2D(painted, -1, motion_kernel(60.0, 0.0), borderType=cv2.BORDER_REFLECT)
    smeared = np.clip(smeared + np.random.default_rng(5).normal(0.0, 2.0, smeared.shape), 0, 255).astype(np.uint8)
    told = replace(blur, image=SmearedImage(smeared, grass, 1.0))
    off = camera.replace(pan_rad=camera.pan_rad + 40.0 / camera.focal_px)
    for cam in (camera, off):
        assert confidence_parts(cam, marks, CURVES, field_mask=grass, motion_blur=told)["template_samples"] > \
            confidence_parts(cam, marks, CURVES, field_mask=grass, motion_blur=blur)["template_samples"]
    # The true camera stays confident; the camera off across the smear loses the markings it lays there.
    assert camera_confidence(camera, marks, CURVES, field_mask=grass, motion_blur=told) > 0.9
    assert camera_confidence(off, marks, CURVES, field_mask=grass, motion_blur=told) < \
        camera_confidence(off, marks, CURVES, field_mask=grass, motion_blur=blur) - 0.1
    # Asked of nothing: as before.
    assert camera_confidence(off, marks, CURVES, ConfidenceConfig(min_checked_smeared_contrast=1.0), field_mask=grass,
                             motion_blur=told) == camera_confidence(off, marks, CURVES, field_mask=grass,
                                                                    motion_blur=blur)
