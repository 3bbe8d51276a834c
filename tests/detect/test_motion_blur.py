"""The straight motion blur found from a frame alone and undone (detect/motion_blur.py)."""

import math

import cv2
import numpy as np
import pytest

from broadtrack_graph.detect.motion_blur import (
    MotionBlur,
    MotionBlurConfig,
    deblurred,
    estimate_motion_blur,
    motion_kernel,
    periodic_extension,
)


def _scene(seed: int = 0, h: int = 540, w: int = 960) -> np.ndarray:
    """A grass-like grey image: fine texture, a few thin bright lines in several directions, small dark blobs."""
    rng = np.random.default_rng(seed)
    image = 100.0 + 8.0 * rng.standard_normal((h, w))
    image = cv2.GaussianBlur(image, (0, 0), 0.7)
    for _ in range(4):
        x0, y0 = rng.uniform(0, w), rng.uniform(0, h)
        angle = rng.uniform(0, math.pi)
        length = rng.uniform(200, 500)
        x1, y1 = x0 + length * math.cos(angle), y0 + length * math.sin(angle)
        cv2.line(image, (int(x0), int(y0)), (int(x1), int(y1)), 160.0, 2, cv2.LINE_AA)
    for _ in range(15):
        cx, cy = int(rng.uniform(0, w)), int(rng.uniform(0, h))
        cv2.ellipse(image, (cx, cy), (5, 14), 0, 0, 360, 60.0, -1, cv2.LINE_AA)
    return np.clip(image, 0, 255).astype(np.float32)


def _smeared(image: np.ndarray, length_px: float, angle_deg: float) -> np.ndarray:
    """The image averaged over 64 shifted copies along a segment (made apart from :func:`motion_kernel`)."""
    h, w = image.shape
    c, s = math.cos(math.radians(angle_deg)), math.sin(math.radians(angle_deg))
    total = np.zeros_like(image)
    for t in np.linspace(-length_px / 2, length_px / 2, 64):
        shift = np.float32([[1, 0, t * c], [0, 1, t * s]])
        total += cv2.warpAffine(image, shift, (w, h), borderMode=cv2.BORDER_REFLECT)
    return total / 64


def _angle_apart(a: float, b: float) -> float:
    d = abs(a - b) % 180.0
    return min(d, 180.0 - d)


def test_the_kernel_is_a_unit_segment_of_the_length_and_direction_asked():
    kernel = motion_kernel(12.0, 30.0).astype(float)
    assert kernel.sum() == pytest.approx(1.0, abs=1e-6)
    k = kernel.shape[0] // 2
    ys, xs = np.mgrid[-k:k + 1, -k:k + 1]
    along = xs * math.cos(math.radians(30)) + ys * math.sin(math.radians(30))
    across = -xs * math.sin(math.radians(30)) + ys * math.cos(math.radians(30))
    # A box of length L has variance L^2 / 12 along it; sharing points among pixels adds under a pixel's worth.
    assert np.sqrt((kernel * along**2).sum()) == pytest.approx(12.0 / math.sqrt(12.0), abs=0.3)
    assert np.sqrt((kernel * across**2).sum()) < 0.5
    assert np.allclose(kernel, kernel[::-1, ::-1], atol=1e-6)  # centred


@pytest.mark.parametrize("length_px, angle_deg", [(10.0, 0.0), (12.0, 35.0), (18.0, 100.0), (24.0, 150.0)])
def test_a_smear_s_length_and_direction_are_found(length_px, angle_deg):
    blurred = _smeared(_scene(1), length_px, angle_deg)
    found = estimate_motion_blur(blurred)
    assert found is not None
    assert found.length_px == pytest.approx(length_px, abs=0.5 + 0.1 * length_px)
    assert _angle_apart(found.angle_deg, angle_deg) <= 3.0
    assert found.depth <= MotionBlurConfig.max_depth


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_a_sharp_image_shows_no_smear(seed):
    assert estimate_motion_blur(_scene(seed)) is None


def _striped(seed: int, stripe_deg: float, h: int = 540, w: int = 960) -> np.ndarray:
    """:func:`_scene` crossed by bright lines 60 px apart all along ``stripe_deg``: a direction of its own."""
    image = _scene(seed, h, w).copy()
    c, s = math.cos(math.radians(stripe_deg)), math.sin(math.radians(stripe_deg))
    for offset in np.arange(-7, 7) * 60.0:
        x, y = w / 2 - s * offset, h / 2 + c * offset
        cv2.line(image, (int(x - 1200 * c), int(y - 1200 * s)), (int(x + 1200 * c), int(y + 1200 * s)), 170.0, 3,
                 cv2.LINE_AA)
    return image


@pytest.mark.parametrize("seed", [1, 2, 3])
@pytest.mark.parametrize("length_px, stripes_off_deg", [(14.0, 25.0), (18.0, 35.0)])
def test_a_smear_is_found_along_its_own_direction_when_the_scene_pulls_the_structure_tensor_off(
        seed, length_px, stripes_off_deg):
    # Lines all one way pull the gradient's least-energy direction off the smear's by more than the full-size
    # refinement reaches, where no lobe is deep enough: the reduced image's deepest lobe near it brings it back.
    blurred = _smeared(_striped(seed, 130.0 + stripes_off_deg), length_px, 130.0)
    found = estimate_motion_blur(blurred)
    assert found is not None
    assert _angle_apart(found.angle_deg, 130.0) <= 3.0
    assert found.length_px == pytest.approx(length_px, abs=1.0)
    assert estimate_motion_blur(blurred, MotionBlurConfig(scan_angle_deg=0.0)) is None
    assert estimate_motion_blur(_striped(seed, 130.0 + stripes_off_deg)) is None  # the lines alone: sharp


def test_a_smear_within_the_frame_s_own_lobe_is_not_told_apart():
    assert estimate_motion_blur(_smeared(_scene(2), 3.0, 20.0)) is None
    assert estimate_motion_blur(_smeared(_scene(2), 6.0, 20.0)) is None


def test_flat_tiny_or_switched_off_images_show_none():
    assert estimate_motion_blur(np.full((540, 960), 90, np.uint8)) is None
    assert estimate_motion_blur(np.zeros((20, 30), np.uint8)) is None
    assert estimate_motion_blur(_smeared(_scene(1), 15.0, 60.0), MotionBlurConfig(min_length_px=0)) is None


def test_undoing_the_smear_brings_a_line_across_it_back():
    """A 3 px line across a 15 px smear keeps about a fifth of its contrast; the Wiener filter nearly triples what is
    left (the line at about half its contrast again) and leaves the grass's level where it was."""
    h, w = 540, 960
    image = np.full((h, w), 100.0, np.float32)
    image[:, 478:481] = 200.0  # a vertical line, 3 px
    image += np.random.default_rng(4).normal(0.0, 2.0, image.shape).astype(np.float32)
    blurred = _smeared(image, 15.0, 0.0)  # smeared across it
    restored = deblurred(np.clip(blurred, 0, 255).astype(np.uint8), MotionBlur(15.0, 0.0, -0.5, 0.1)).astype(float)
    row = slice(200, 340)

    def contrast(img):
        return float(img[row, 476:483].mean(axis=0).max() - np.median(img[row, 300:400]))

    assert contrast(blurred) < 25.0
    assert contrast(restored) > 2.6 * contrast(blurred)
    assert np.median(restored[row, 300:400]) == pytest.approx(100.0, abs=3.0)
    assert restored.shape == (h, w)


def test_the_extension_meets_the_image_s_opposite_borders_without_a_step():
    """Repeated periodically, the extended image runs from each border to the opposite one in small steps; the image
    itself is kept as it is."""
    rng = np.random.default_rng(2)
    image = np.vstack([np.full((30, 50), 80.0), np.full((30, 50), 160.0)]).astype(np.float32)
    image += rng.normal(0.0, 1.0, image.shape).astype(np.float32)
    out = periodic_extension(image, 96, 72)
    assert out.shape == (96, 72) and out.dtype == np.float32
    np.testing.assert_array_equal(out[:60, :50], image)
    tiled = np.vstack([out, out[:1]])  # the first row again after the last: the wrap
    assert np.abs(np.diff(tiled[:, :50], axis=0))[59:].max() < 80.0 / 36 * 1.6 + 1.0  # 80 levels over 36 rows
    tiled = np.hstack([out, out[:, :1]])
    assert np.abs(np.diff(tiled[:60], axis=1))[:, 49:].max() < 5.0  # the left and right borders alike but for noise


def test_a_smeared_frame_whose_top_and_bottom_differ_gets_no_band_along_its_borders():
    """A step between the frame's opposite borders (stands at the top, grass at the bottom) deconvolved as the
    Fourier transform repeats the image would ring back in along both borders: the bottom rows brightened into a band
    a ridge detector reads as a marking along the frame's edge. The grass's rows keep their level to the last."""
    h, w = 540, 960
    rng = np.random.default_rng(5)
    image = np.full((h, w), 110.0, np.float32)
    image[:200] = 85.0  # the stands
    image += rng.normal(0.0, 2.0, image.shape).astype(np.float32)
    blurred = np.clip(_smeared(image, 13.0, 99.0), 0, 255).astype(np.uint8)
    restored = deblurred(blurred, MotionBlur(13.0, 99.0, -0.5, 0.1)).astype(float)
    bottom = restored[h - 12:, 100:860].mean(axis=1)
    assert np.abs(bottom - 110.0).max() < 2.0
    top = restored[:6, 100:860].mean(axis=1)
    assert np.abs(top - 85.0).max() < 3.0


def test_the_detector_finds_a_smeared_frame_s_markings_again():
    """Frame 55 of ``bench placements --random --seed 3 --renderer plain``: a camera on the main stand's side, its frame
    smeared over 17 px at 1280 px (13 at the working width) along about 100 deg. As it comes, the markings the
    detector finds (a blurred frame's, wide ones with them) do not fix the camera and the true camera explains less
    than half of them; with the smear undone they fix it and it explains most."""
    from broadtrack_graph.benchmarks.placement_frames import draw_frame
    from broadtrack_graph.detect.weightfree import WeightFreeDetector
    from broadtrack_graph.detect.weightfree_config import WeightFreeConfig
    from broadtrack_graph.geometry.determinable import determinability
    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.geometry.template import TemplateCurves
    from broadtrack_graph.reinit.confidence import confidence_parts

    pitch = PitchTemplate()
    frame = draw_frame(3, 55, 1280, 720, [], "plain")
    truth, look = frame["drawn"].camera, frame["look"]
    _, grey, scale = WeightFreeDetector(pitch).working_images(frame["image"])
    smear = estimate_motion_blur(grey)
    assert smear is not None
    assert _angle_apart(smear.angle_deg, -look.motion_angle_deg) <= 5.0
    assert smear.length_px == pytest.approx(look.motion_blur_px * scale, abs=1.5)
    curves = TemplateCurves(pitch)
    undone = WeightFreeDetector(pitch).detect(frame["image"])
    as_it_comes = WeightFreeDetector(pitch, WeightFreeConfig(motion_blur=MotionBlurConfig(min_length_px=0))).detect(
        frame["image"])
    assert determinability(truth, pitch, explained_by=undone.marking_mask).determinable
    assert not determinability(truth, pitch, explained_by=as_it_comes.marking_mask).determinable
    # The detections carry the smear, its length in frame pixels (the confidence's: reinit.confidence).
    assert undone.motion_blur.length_px == pytest.approx(smear.length_px / scale)
    assert undone.motion_blur.angle_deg == pytest.approx(smear.angle_deg) and as_it_comes.motion_blur is None
    assert confidence_parts(truth, undone.marking_mask, curves, field_mask=undone.field_mask)["confidence"] >= 0.7
    assert confidence_parts(truth, as_it_comes.marking_mask, curves, field_mask=as_it_comes.field_mask)[
        "confidence"] < 0.5


def test_a_sharp_real_looking_frame_is_left_as_it_is():
    """The project's own renderer's sharp frames (a `clean` look) show no smear: the detector's markings are those
    found with the search switched off."""
    from broadtrack_graph.benchmarks.placement_frames import draw_frame
    from broadtrack_graph.detect.weightfree import WeightFreeDetector
    from broadtrack_graph.detect.weightfree_config import WeightFreeConfig

    frame = draw_frame(3, 0, 1280, 720, ["clean"])
    found = WeightFreeDetector().find_markings(frame["image"])
    never = WeightFreeDetector(config=WeightFreeConfig(motion_blur=MotionBlurConfig(min_length_px=0))).find_markings(
        frame["image"])
    np.testing.assert_array_equal(found.points_work_px, never.points_work_px)
    assert found.unnamed.motion_blur is None


def test_a_smeared_frame_s_true_camera_is_not_marked_down_for_the_markings_the_smear_wiped_out():
    """Frame 93 of ``bench placements --random --seed 3 --renderer plain``: a camera behind the goal smeared over 22 px
    at 1280 px. The markings across the smear are not found even with it undone: judged as a sharp frame, the true
    camera's confidence is about half; told the smear, it is judged on the markings the smear leaves (and as far as
    the map shows the others), and its confidence is that of a sharp frame's true camera. Those the smear leaves
    0.03-0.075 of their contrast asked of the smeared image as well (the detector keeps it with the blur), about half
    of them show their bands over the grass here (a mown stripe's edge beside some): the true camera stays over the
    court model's bar, and a camera 20 px off across the smear is far under it."""
    from dataclasses import replace

    from broadtrack_graph.benchmarks.placement_frames import draw_frame
    from broadtrack_graph.detect.weightfree import WeightFreeDetector
    from broadtrack_graph.geometry.template import TemplateCurves
    from broadtrack_graph.reinit.confidence import camera_confidence

    frame = draw_frame(3, 93, 1280, 720, [], "plain")
    truth, found = frame["drawn"].camera, WeightFreeDetector().detect(frame["image"])
    curves = TemplateCurves()
    assert found.motion_blur is not None and found.motion_blur.length_px > 15 and found.motion_blur.image is not None

    def confidence(camera, blur):
        return camera_confidence(camera, found.marking_mask, curves, field_mask=found.field_mask,
                                 player_mask=found.player_mask, motion_blur=blur)

    as_sharp, told = confidence(truth, None), confidence(truth, replace(found.motion_blur, image=None))
    assert as_sharp < 0.6 and told > 0.85
    asked = confidence(truth, found.motion_blur)
    off = truth.replace(tilt_rad=truth.tilt_rad + 20.0 / truth.focal_px)
    assert 0.7 < asked < told and confidence(off, found.motion_blur) < 0.3


def test_a_lobe_is_its_own_not_the_tail_of_the_derivative_s_own():
    from broadtrack_graph.detect.motion_blur import _lobe

    lags = np.arange(1.0, 11.0)
    own_tail = np.array([0.6, -0.3, -0.28, -0.2, -0.1, -0.05, 0.0, 0.0, 0.0, 0.0])  # deepest from 3 on: at 3, a tail
    assert _lobe(own_tail, lags, 3.0) is None
    smear = np.array([0.8, 0.6, 0.4, 0.2, 0.0, -0.2, -0.4, -0.3, -0.1, 0.0])  # a lobe at 7
    assert _lobe(smear, lags, 3.0) == 6
    longer = np.array([0.9, 0.8, 0.7, 0.6, 0.5, 0.4, 0.3, 0.2, 0.1, -0.1])  # deepest at the last lag: a longer smear
    assert _lobe(longer, lags, 3.0) is None
