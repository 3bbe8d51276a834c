"""An image read at many points at once: every point as it would be read alone, past OpenCV's 32767-point maps."""

import cv2
import numpy as np
import pytest

from broadtrack_graph.detect.image_reads import read_at


def _alone(image, x, y):
    """One point at a time through OpenCV's own remap (a 1x1 map each)."""
    out = [cv2.remap(image, np.float32([[a]]), np.float32([[b]]), cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
           for a, b in zip(x.ravel(), y.ravel())]
    return np.array(out).reshape(*x.shape, *image.shape[2:])


@pytest.mark.parametrize("channels", [None, 3])
def test_points_are_read_as_alone_whatever_the_shape_asked(channels):
    rng = np.random.default_rng(0)
    shape = (40, 60) if channels is None else (40, 60, channels)
    image = rng.uniform(0, 255, shape).astype(np.float32)
    x = rng.uniform(-3, 63, (7, 9)).astype(np.float32)  # off the image too: its border repeated
    y = rng.uniform(-3, 43, (7, 9)).astype(np.float32)
    out = read_at(image, x, y)
    assert out.shape == x.shape + image.shape[2:]
    np.testing.assert_array_equal(out, _alone(image, x, y))


def test_more_points_than_opencv_takes_in_one_map_side_are_read():
    """A smear undone into noise can leave a frame with over 32767 marking points; one column of them is refused."""
    image = np.arange(100 * 200, dtype=np.float32).reshape(100, 200)
    n = 40_000
    x = np.linspace(0, 199, n).astype(np.float32)
    y = np.linspace(0, 99, n).astype(np.float32)
    with pytest.raises(cv2.error):
        cv2.remap(image, x.reshape(-1, 1), y.reshape(-1, 1), cv2.INTER_LINEAR)
    out = read_at(image, x, y)
    assert out.shape == (n,) and out.dtype == np.float32
    every = slice(None, None, 997)
    np.testing.assert_array_equal(out[every], _alone(image, x[every], y[every]))
    # bilinear on a ramp: the value at (x, y) is 200 y + x, to OpenCV's fixed-point interpolation
    np.testing.assert_allclose(out, 200 * y + x, atol=200 / 32 + 1 / 32 + 1e-3)


def test_no_points_read_nothing():
    image = np.zeros((10, 10), np.uint8)
    assert read_at(image, np.zeros(0, np.float32), np.zeros(0, np.float32)).shape == (0,)
