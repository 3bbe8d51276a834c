"""The weight-free detector's marking ridges (detect/ridges.py), on images drawn here: thin lines, wide lines, stripes."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from broadtrack_graph.detect.ridges import marking_channel, marking_ridges, white, wide_ridges
from broadtrack_graph.detect.weightfree import WeightFreeDetector
from broadtrack_graph.detect.weightfree_config import WeightFreeConfig

W, H = 320, 200


def _ridges(grey, allowed=None, grass=None, config=WeightFreeConfig(), follow_faint=False):
    detector = WeightFreeDetector(config=config)
    allowed = np.full((H, W), 255, np.uint8) if allowed is None else allowed
    points, _, candidates = marking_ridges(grey, allowed, grass, detector._tophat_kernel, detector._ridge_kernel,
                                           config, follow_faint)
    return points, candidates


def _line_image(offset_px: float, slope: float = 0.2, width_px: float = 3.0, level: float = 60.0):
    """Grass (grey 90) with one bright line y = 100 + offset + slope (x - 160), ``width_px`` wide, drawn
    antialiased by the distance of each pixel centre to the line."""
    rows, cols = np.mgrid[0:H, 0:W].astype(float)
    distance = np.abs(rows - (100.0 + offset_px + slope * (cols - 160.0))) / np.hypot(1.0, slope)
    cover = np.clip(width_px / 2 + 0.5 - distance, 0.0, 1.0)
    return np.clip(90.0 + level * cover, 0, 255).astype(np.uint8)


def test_points_lie_on_the_line_centre_to_a_fraction_of_a_pixel():
    for offset in (0.0, 0.3, 0.5):
        points, candidates = _ridges(_line_image(offset))
        assert len(points) > 200 and candidates.any()
        inside = (points[:, 0] > 20) & (points[:, 0] < W - 20)  # the line's ends at the image border apart
        distance = np.abs(points[:, 1] - (100.0 + offset + 0.2 * (points[:, 0] - 160.0))) / np.hypot(1.0, 0.2)
        assert np.median(distance) < 0.1 and np.max(distance[inside]) < 0.6


def test_specks_and_faint_lines_give_no_points_and_where_markings_may_not_be_gives_none():
    specks = np.full((H, W), 90, np.uint8)
    for x in range(15, W, 30):
        for y in range(15, H, 30):
            cv2.circle(specks, (x, y), 1, 200, -1)  # isolated bright dots: too little support around each
    assert len(_ridges(specks)[0]) == 0
    assert len(_ridges(_line_image(0.0, level=10.0))[0]) == 0  # 10 grey levels: under the fixed threshold
    allowed = np.zeros((H, W), np.uint8)
    allowed[:, :100] = 255
    points, _ = _ridges(_line_image(0.0), allowed)
    assert len(points) > 50 and points[:, 0].max() < 101


def test_the_threshold_rises_with_the_grass_texture():
    # A line 45 grey levels over grass noisy enough that the 90th percentile of its top-hat passes the fixed level:
    # with the grass map the threshold rises above the noise and only the line's points stay.
    rng = np.random.default_rng(2)
    noisy = np.clip(_line_image(0.0, level=45.0).astype(float) + rng.normal(0, 6, (H, W)), 0, 255).astype(np.uint8)
    grass = np.full((H, W), 255, np.uint8)
    plain, _ = _ridges(noisy)
    adapted, _ = _ridges(noisy, grass=grass)
    on_line = np.abs(adapted[:, 1] - (100.0 + 0.2 * (adapted[:, 0] - 160.0))) < 2.0
    assert len(plain) > 10 * len(adapted)  # the fixed level takes the noise for thousands of ridge points
    assert on_line.mean() > 0.95 and on_line.sum() > 300


def test_a_blurred_frame_s_faint_line_is_followed_from_its_brighter_stretches():
    # A line 10 grey levels over grass (under the threshold, over the faint level) with three short stretches of 40:
    # followed from them along its whole length when asked (a blurred frame's), else only those stretches are found;
    # the faint line alone gives nothing either way.
    faint = _line_image(0.0, level=10.0)
    bright = _line_image(0.0, level=40.0)
    touched = faint.copy()
    for x0 in (40, 150, 260):
        touched[:, x0:x0 + 6] = bright[:, x0:x0 + 6]
    assert len(_ridges(faint, follow_faint=True)[0]) == 0
    followed, _ = _ridges(touched, follow_faint=True)
    on_line = np.abs(followed[:, 1] - (100.0 + 0.2 * (followed[:, 0] - 160.0))) < 1.0
    assert on_line.mean() > 0.95 and on_line.sum() > 250  # well beyond the 18 columns of the bright stretches
    assert len(_ridges(touched)[0]) < 60


def test_white_paint_is_kept_and_a_coloured_line_is_dropped_however_faint():
    # Grass (BGR 60, 140, 70) with a white line at y = 60 and a yellow one at y = 140, each drawn at full strength and
    # mixed a fifth into the grass (a faint or thin line): the points on the white line are kept, the yellow's dropped.
    grass = np.array([60.0, 140.0, 70.0])
    for share in (1.0, 0.2):
        image = np.tile(grass, (H, W, 1))
        for y, paint in ((60, (235.0, 240.0, 240.0)), (140, (30.0, 220.0, 235.0))):
            image[y - 1:y + 2] = (1 - share) * grass + share * np.array(paint)
        image = image.astype(np.uint8)
        xs = np.arange(20.0, W - 20.0, 5.0)
        on_white = np.column_stack([xs, np.full(len(xs), 60.0)])
        on_yellow = np.column_stack([xs, np.full(len(xs), 140.0)])
        assert white(image, on_white, 6.0).all()
        assert not white(image, on_yellow, 6.0).any()



def test_white_reads_more_points_than_opencv_takes_in_one_map():
    """A frame whose smear is undone into noise can hold over 32767 marking points: each is still judged."""
    grass = np.array([60.0, 140.0, 70.0])
    image = np.tile(grass, (H, W, 1))
    image[59:62] = (235.0, 240.0, 240.0)
    image = image.astype(np.uint8)
    xs = np.resize(np.arange(20.0, W - 20.0, 0.25), 40_000)
    kept = white(image, np.column_stack([xs, np.full(len(xs), 60.0)]), 6.0)
    assert kept.shape == (40_000,) and kept.all()


def _wide(grey, config=WeightFreeConfig()):
    """The working level's points, then the wide markings' (detect.ridges.wide_ridges), markings allowed anywhere."""
    detector = WeightFreeDetector(config=config)
    allowed = np.full(grey.shape, 255, np.uint8)
    points, peaked, _ = marking_ridges(grey, allowed, None, detector._tophat_kernel, detector._ridge_kernel, config)
    return points, wide_ridges(grey, allowed, None, points, peaked, detector._tophat_kernel, detector._ridge_kernel,
                               config)


def _distance_to_line(points, offset_px: float, slope: float) -> np.ndarray:
    return np.abs(points[:, 1] - (100.0 + offset_px + slope * (points[:, 0] - 160.0))) / np.hypot(1.0, slope)


def test_lines_wider_than_the_kernel_give_their_centre_not_their_edges():
    # A zoomed view's or a low camera's near line, 8-24 px wide: the working level gives nothing or points off its
    # centre; with the reduced levels, a row of points on its centre line and none on its edges.
    for slope in (0.02, 0.3, 1.0, 4.0):
        for width in (8.0, 12.0, 16.0, 24.0):
            image = cv2.GaussianBlur(_line_image(0.3, slope=slope, width_px=width, level=50.0), (0, 0), 1.0)
            working, points = _wide(image)
            inside = (points[:, 0] > 40) & (points[:, 0] < W - 40) & (points[:, 1] > 40) & (points[:, 1] < H - 40)
            distance = _distance_to_line(points[inside], 0.3, slope)
            assert inside.sum() >= 10, (slope, width)
            assert np.max(distance) < 0.25 * width and np.median(distance) < 0.5, (slope, width)
            working = working[(working[:, 0] > 40) & (working[:, 0] < W - 40)]
            assert width < 10 or not len(working) or np.median(_distance_to_line(working, 0.3, slope)) > 0.5


def test_narrow_lines_keep_their_points_with_the_reduced_levels():
    for width in (2.0, 3.0, 5.0):
        working, points = _wide(_line_image(0.3, width_px=width))
        assert len(working) > 200 and np.array_equal(points, working)


def test_a_soft_wide_stripe_is_not_a_wide_marking():
    # A mown stripe or a soft band of light, as bright as paint and as wide as a zoomed line but without its sharp
    # edges: the reduced levels find its ridge and leave it (the working level finds none on it either).
    rows, cols = np.mgrid[0:H, 0:W].astype(float)
    distance = (rows - (100.0 + 0.3 * (cols - 160.0))) / np.hypot(1.0, 0.3)
    stripe = np.clip(90.0 + 50.0 * np.exp(-0.5 * (distance / 6.0) ** 2), 0, 255).astype(np.uint8)
    assert len(_wide(stripe)[1]) == 0
    assert len(_wide(stripe, WeightFreeConfig(wide_edge_share=0.0))[1]) > 50  # the rule is what leaves it


def test_faint_white_paint_stands_out_in_the_least_channel_and_a_yellow_line_does_not():
    # Grass (B, G, R) = (50, 130, 60), luma about 100; a white line (200) covering 12 % of its pixels: 12 grey levels
    # over the grass in luma (under the fixed threshold of 14), 18 in the least channel (50 -> 200). A yellow line
    # (B 40, G 230, R 230) as bright as paint in luma is darker than grass in blue.
    rows, cols = np.mgrid[0:H, 0:W].astype(float)
    image = np.empty((H, W, 3), float)
    image[:] = (50.0, 130.0, 60.0)
    white_line = np.abs(rows - 70.0) < 1.5
    image[white_line] = 0.88 * image[white_line] + 0.12 * 200.0
    yellow_line = np.abs(rows - 140.0) < 1.5
    image[yellow_line] = (40.0, 230.0, 230.0)
    image = image.round().astype(np.uint8)
    least, luma = marking_channel(image, "min"), marking_channel(image, "luma")
    assert least[70, 10] - least[20, 10] == 18 and luma[70, 10] - luma[20, 10] == 12
    for channel, white_found in ((least, True), (luma, False)):
        points, _ = _ridges(channel)
        near_white = np.abs(points[:, 1] - 70.0) < 2.0
        near_yellow = np.abs(points[:, 1] - 140.0) < 2.0
        assert (near_white.sum() > 200) == white_found
        assert near_yellow.sum() == 0 if channel is least else near_yellow.sum() > 200
    with pytest.raises(ValueError, match="marking channel"):
        marking_channel(image, "green")
