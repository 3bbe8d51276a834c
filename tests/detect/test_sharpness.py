"""How blurred a frame is: edge widths of drawn images, sharp, blurred and enlarged."""

from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.detect.sharpness import SHARP_EDGE_WIDTH_PX, blur_factor, edge_width_px


def _squares(width: int = 960, height: int = 540) -> np.ndarray:
    """Grey squares on darker grass with white bars: many step edges in every direction."""
    rng = np.random.default_rng(1)
    image = np.full((height, width), 70, np.uint8)
    for _ in range(40):
        x, y = int(rng.integers(20, width - 80)), int(rng.integers(20, height - 80))
        size = int(rng.integers(20, 60))
        cv2.rectangle(image, (x, y), (x + size, y + size), int(rng.integers(120, 220)), -1)
    for k in range(6):
        cv2.line(image, (0, 60 + 80 * k), (width, 100 + 70 * k), 230, 3)
    return image


def test_a_sharp_image_s_edges_are_about_two_pixels_wide_and_a_box_blur_widens_them():
    sharp = _squares()
    width = edge_width_px(sharp)
    assert 1.8 <= width <= 1.3 * SHARP_EDGE_WIDTH_PX
    widths = [edge_width_px(cv2.blur(sharp, (k, k))) for k in (3, 5, 9)]
    assert widths[0] < widths[1] < widths[2]
    assert 0.4 * 9 <= widths[2] <= 9  # a 9 px box spreads a step over up to 9 px (less where squares' edges meet)


def test_a_frame_enlarged_to_the_working_width_is_sharp_at_its_own_pixels_and_a_blurred_one_is_not():
    small = cv2.resize(_squares(), (640, 360), interpolation=cv2.INTER_AREA)
    enlarged = cv2.resize(small, (960, 540), interpolation=cv2.INTER_LINEAR)
    assert edge_width_px(enlarged) > 1.2 * edge_width_px(_squares())  # wider in working pixels ...
    assert blur_factor(enlarged, 640) < 1.2  # ... but as sharp as 640 px allow
    assert blur_factor(cv2.blur(_squares(), (9, 5)), 960) >= 1.4  # a pan and a tilt's blur


def test_an_image_too_small_to_tell_counts_as_sharp():
    assert edge_width_px(np.zeros((20, 20), np.uint8)) is None
    assert blur_factor(np.zeros((20, 20), np.uint8), 20) == 1.0


def test_the_strongest_edges_are_those_of_ranking_every_pixel_s_gradient():
    """The candidates taken only where one derivative reaches the level over sqrt(2) are the pixels a full ranking
    of the gradient's length over the level gives: the same set, on textured, blurred and flat images."""
    from broadtrack_graph.detect.sharpness import _magnitude, _strongest

    rng = np.random.default_rng(4)
    images = [_squares(), cv2.blur(_squares(), (7, 3)), rng.integers(0, 256, (120, 160), dtype=np.uint8),
              cv2.GaussianBlur(rng.integers(0, 256, (200, 300), dtype=np.uint8), (0, 0), 3.0)]
    for image in images:
        gx16 = cv2.Sobel(image, cv2.CV_16S, 1, 0, ksize=3)
        gy16 = cv2.Sobel(image, cv2.CV_16S, 0, 1, ksize=3)
        magnitude = cv2.magnitude(gx16.astype(np.float32) / 8, gy16.astype(np.float32) / 8)
        np.testing.assert_allclose(_magnitude(gx16, gy16), magnitude, rtol=1e-6)
        count = 500
        rows, cols, lengths = _strongest(gx16, gy16, count)
        assert len(set(zip(rows.tolist(), cols.tolist()))) == count
        np.testing.assert_array_equal(lengths, _magnitude(gx16[rows, cols], gy16[rows, cols]))
        # Every pixel left out is no longer than the shortest taken.
        taken = np.zeros(image.shape, bool)
        taken[rows, cols] = True
        assert _magnitude(gx16, gy16)[~taken].max() <= lengths.min()


def test_the_blur_of_a_region_is_read_from_its_own_edges_not_from_sharp_ones_around_it():
    """A pan smears the pitch (the lower half) while sharp blocks above it (a crowd, a graphic) have the strongest
    edges: the whole frame reads sharp, the pitch's region as blurred as it is."""
    rng = np.random.default_rng(4)
    crowd = np.kron(rng.integers(20, 200, (34, 120)), np.ones((8, 8))).astype(np.uint8)[:270, :960]
    pitch = cv2.blur(_squares(960, 270), (9, 9))
    image = np.vstack([crowd, pitch])
    region = np.zeros(image.shape, np.uint8)
    region[290:, :] = 1
    assert blur_factor(image, 960) < 1.4
    assert blur_factor(image, 960, region) >= 1.8
    assert abs(blur_factor(image, 960, region) - blur_factor(pitch, 960)) < 0.25
    tiny = np.zeros(image.shape, np.uint8)
    tiny[300:310, 100:200] = 1  # too few pixels to tell: the whole image's
    assert blur_factor(image, 960, tiny) == blur_factor(image, 960)
