"""Tests of the field-model training samples: determinism, exact labels, negatives, kinds, randomisation switches."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from broadtrack_graph.geometry.pitch import LINE_CLASSES, PitchTemplate
from broadtrack_graph.synth.field_cameras import FIELD_KIND_NAMES, KIND_CLOSE_UP, KIND_CROWD, NEGATIVE_KINDS
from broadtrack_graph.synth.field_config import SampleConfig
from broadtrack_graph.synth.field_samples import (
    FIELD_KEYPOINTS_W,
    SCHEDULE_BLOCK,
    render_camera_for,
    render_size,
    sample_field,
    sample_kind,
)
from broadtrack_graph.synth.render import Renderer

W, H = 320, 180
CONFIG = SampleConfig(texture_variants=1)  # one texture seed: one texture build for the whole module
SEED = 7


def _first_index(kinds, config=CONFIG, seed=SEED) -> int:
    return next(i for i in range(200) if sample_kind(seed, i, config) in kinds)


@pytest.fixture(scope="module")
def pitch_samples():
    indices = [i for i in range(12) if sample_kind(SEED, i, CONFIG) not in NEGATIVE_KINDS][:5]
    return [sample_field(SEED, i, W, H, CONFIG) for i in indices]


def test_the_same_seed_and_index_give_the_same_sample_and_another_index_another(pitch_samples):
    first = pitch_samples[0]
    index = next(i for i in range(12) if sample_kind(SEED, i, CONFIG) == first.kind)
    again = sample_field(SEED, index, W, H, CONFIG)
    np.testing.assert_array_equal(first.image_bgr, again.image_bgr)
    np.testing.assert_array_equal(first.camera.to_vector(), again.camera.to_vector())
    np.testing.assert_array_equal(first.keypoints_px, again.keypoints_px)
    np.testing.assert_array_equal(first.keypoint_visible, again.keypoint_visible)
    np.testing.assert_array_equal(first.line_masks, again.line_masks)
    assert first.info == again.info
    other = pitch_samples[1]
    assert np.abs(first.image_bgr.astype(int) - other.image_bgr.astype(int)).mean() > 5
    assert not np.allclose(first.camera.to_vector(), other.camera.to_vector())


def test_shapes_and_types(pitch_samples):
    for sample in pitch_samples:
        assert sample.image_bgr.shape == (H, W, 3) and sample.image_bgr.dtype == np.uint8
        assert (sample.camera.width_px, sample.camera.height_px) == (W, H)
        assert sample.kind in FIELD_KIND_NAMES
        assert sample.keypoints_px.shape == (57, 2) and sample.keypoint_visible.shape == (57,)
        assert sample.line_masks.shape == (len(LINE_CLASSES), H // 4, W // 4) and sample.line_masks.dtype == bool
        assert sample.line_masks.any() and sample.keypoint_visible.any()


def test_keypoints_are_the_camera_projection_of_the_nbjw_points_and_visible_ones_lie_in_the_image(pitch_samples):
    for sample in pitch_samples:
        uv, front = sample.camera.project(FIELD_KEYPOINTS_W)
        np.testing.assert_allclose(sample.keypoints_px[front], uv[front], atol=1e-9)
        assert np.isnan(sample.keypoints_px[~front]).all()
        visible = sample.keypoints_px[sample.keypoint_visible]
        assert (visible >= 0).all() and (visible[:, 0] <= W - 1).all() and (visible[:, 1] <= H - 1).all()
        assert not (sample.keypoint_visible & ~front).any()
    # Number 51 is the centre spot and number 1 the far-left corner flag of the NBJW numbering.
    np.testing.assert_array_equal(FIELD_KEYPOINTS_W[50], [0.0, 0.0, 0.0])
    np.testing.assert_array_equal(FIELD_KEYPOINTS_W[0], [-52.5, -34.0, 0.0])


def test_a_keypoint_behind_a_player_is_not_visible():
    config = SampleConfig.plain(player_count_range=(30, 30), player_spread_range_m=(1.0, 1.0), texture_variants=1,
                                negative_share=0.0)
    hidden = 0
    for index in range(6):
        sample = sample_field(SEED, index, W, H, config)
        uv, front = sample.camera.project(FIELD_KEYPOINTS_W)
        with np.errstate(invalid="ignore"):
            inside = front & (uv[:, 0] >= 0) & (uv[:, 0] <= W - 1) & (uv[:, 1] >= 0) & (uv[:, 1] <= H - 1)
        assert not (sample.keypoint_visible & ~inside).any()
        hidden += int((inside & ~sample.keypoint_visible).sum())
    assert hidden > 0  # thirty players packed around the aim point cover some keypoints


@pytest.mark.parametrize("kind", [KIND_CLOSE_UP, KIND_CROWD])
def test_a_negative_has_no_camera_no_visible_keypoint_and_empty_masks(kind):
    sample = sample_field(SEED, _first_index({kind}), W, H, CONFIG)
    assert sample.kind == kind and sample.is_negative and sample.camera is None
    assert not sample.keypoint_visible.any() and np.isnan(sample.keypoints_px).all()
    assert not sample.line_masks.any()
    assert sample.image_bgr.shape == (H, W, 3)


def test_each_line_mask_covers_the_projected_template_line_of_its_class():
    config = SampleConfig(texture_variants=1, player_count_range=(0, 0), graphics_share=0.0, negative_share=0.0)
    samples_w = PitchTemplate().sample_soccernet()
    checked = 0
    for index in range(4):
        sample = sample_field(SEED + 1, index, W, H, config)
        grown = np.stack([cv2.dilate(m.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0 for m in sample.line_masks])
        for j, name in enumerate(LINE_CLASSES):
            if name.startswith("Goal"):
                continue
            uv, front = sample.camera.project(samples_w[name])
            with np.errstate(invalid="ignore"):
                inside = front & (uv[:, 0] >= 0) & (uv[:, 0] <= W - 1) & (uv[:, 1] >= 0) & (uv[:, 1] <= H - 1)
            if inside.sum() < 10:
                continue
            cells = np.rint((uv[inside] + 0.5) / 4 - 0.5).astype(int)
            cells = np.clip(cells, 0, [W // 4 - 1, H // 4 - 1])
            assert grown[j][cells[:, 1], cells[:, 0]].mean() >= 0.9, (sample.kind, name)
            checked += 1
    assert checked >= 8


def test_every_camera_kind_and_both_negatives_appear_in_fifty_samples():
    for seed in (0, 1, SEED):
        kinds = [sample_kind(seed, i) for i in range(50)]
        assert set(kinds) == set(FIELD_KIND_NAMES) | set(NEGATIVE_KINDS)
        block = [sample_kind(seed, i) for i in range(SCHEDULE_BLOCK)]
        assert sum(k in NEGATIVE_KINDS for k in block) == round(0.1 * SCHEDULE_BLOCK)
    drawn = [sample_field(SEED, i, 64, 36, SampleConfig.plain(texture_variants=1)).kind for i in range(3)]
    assert drawn == [sample_kind(SEED, i) for i in range(3)]


def test_the_mirrored_kinds_stand_on_both_sides():
    config = SampleConfig.plain(texture_variants=1, camera_kinds=("16m",), negative_share=0.0, mirror_share=0.5)
    sides = {np.sign(sample_field(SEED, i, 64, 36, config).camera.position_m[0]) for i in range(8)}
    assert sides == {-1.0, 1.0}


def test_a_randomisation_switch_changes_the_image_and_nothing_else():
    index = _first_index(set(FIELD_KIND_NAMES))
    on = sample_field(SEED, index, W, H, SampleConfig(texture_variants=1, jpeg_share=1.0, jpeg_quality_range=(10, 10)))
    off = sample_field(SEED, index, W, H, SampleConfig(texture_variants=1, jpeg_share=0.0))
    assert 0.5 < np.abs(on.image_bgr.astype(int) - off.image_bgr.astype(int)).mean() < 20
    np.testing.assert_array_equal(on.camera.to_vector(), off.camera.to_vector())
    np.testing.assert_array_equal(on.keypoints_px, off.keypoints_px)
    no_hue = SampleConfig(texture_variants=1, jpeg_share=0.0, grass_hue_shift_range=None)
    grass_off = sample_field(SEED, index, W, H, no_hue)
    assert np.abs(grass_off.image_bgr.astype(int) - off.image_bgr.astype(int)).mean() > 0.5


def test_with_every_randomisation_off_the_image_is_the_plain_renderers():
    config = SampleConfig.plain(texture_variants=1, negative_share=0.0)
    for index in range(2):
        sample = sample_field(SEED, index, W, H, config)
        renderer = Renderer(W, H, seed=sample.info["look"]["texture_seed"], settings=config.render_settings)
        np.testing.assert_array_equal(sample.image_bgr, renderer.render(sample.camera, sample.players, 0).image)
        assert sample.info["render_size_px"] == (W, H)


def test_resolution_randomisation_renders_at_the_aspect_ratio_and_projects_exactly():
    assert render_size(960, 540, 1080) == (1920, 1080)
    assert render_size(960, 540, 700) == (1248, 702)
    assert render_size(320, 180, None) == (320, 180)
    width, height = render_size(321, 180, 500)
    assert width * 180 == height * 321
    sample = sample_field(SEED, _first_index(set(FIELD_KIND_NAMES)), W, H, CONFIG)
    render_w, render_h = sample.info["render_size_px"]
    assert render_w * H == render_h * W and 360 <= render_h <= 1080
    camera = render_camera_for(sample.camera, render_w, render_h)
    uv, front = sample.camera.project(FIELD_KEYPOINTS_W)
    uv_render, _ = camera.project(FIELD_KEYPOINTS_W)
    scale = W / render_w
    np.testing.assert_allclose(((uv_render + 0.5) * scale - 0.5)[front], uv[front], atol=1e-9)


def test_bad_sizes_and_settings_are_refused():
    with pytest.raises(ValueError, match="divide"):
        sample_field(0, 0, 322, 180)
    with pytest.raises(ValueError, match="index"):
        sample_field(0, -1, W, H)
    with pytest.raises(ValueError, match="seed"):
        sample_field(-3, 0, W, H)
    with pytest.raises(ValueError, match="unknown camera kind"):
        SampleConfig(camera_kinds=("blimp",))
    with pytest.raises(ValueError, match="jpeg_share"):
        SampleConfig(jpeg_share=1.5)
