"""Fixtures of the command tests."""

from __future__ import annotations

import pytest


@pytest.fixture(autouse=True)
def restore_opencv_threads():
    """A command sets OpenCV's threads for its process: the next test starts with the count this one had."""
    import cv2

    before = cv2.getNumThreads()
    yield
    cv2.setNumThreads(before)
