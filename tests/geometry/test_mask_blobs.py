"""blobs_with_stats: the same blobs, labels and stats as OpenCV's default labelling."""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from broadtrack_graph.geometry.mask_blobs import blobs_with_stats


@pytest.mark.parametrize("share", [0.02, 0.3, 0.5, 0.7])
def test_same_as_opencv_default(share):
    mask = (np.random.default_rng(7).random((97, 131)) < share).astype(np.uint8) * 255
    count, labels, stats, centroids = blobs_with_stats(mask)
    want = cv2.connectedComponentsWithStats(mask, connectivity=8)
    assert count == want[0] and count > 2
    np.testing.assert_array_equal(labels, want[1])
    np.testing.assert_array_equal(stats, want[2])
    np.testing.assert_allclose(centroids, want[3])


def test_bool_mask_and_diagonal_neighbours():
    mask = np.zeros((6, 8), bool)
    mask[1, 1] = mask[2, 2] = True  # diagonal: one 8-connected blob
    mask[4, 5:8] = True
    count, labels, stats, _ = blobs_with_stats(mask)
    assert count == 3
    assert labels[1, 1] == labels[2, 2] == 1 and labels[4, 6] == 2
    assert stats[1, cv2.CC_STAT_AREA] == 2 and stats[2, cv2.CC_STAT_WIDTH] == 3
