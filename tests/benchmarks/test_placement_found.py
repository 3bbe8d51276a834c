from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.benchmarks.placement_found import (
    PAINT_WIDTH_BINS_PX,
    TOPHAT_CONTRAST_BINS,
    found_by_tophat_contrast,
    marking_contrast,
    paint_found_by_width,
)
from broadtrack_graph.detect.weightfree import WeightFreeDetector


def test_the_contrast_of_a_line_is_its_step_over_the_grass_at_the_working_size():
    detector = WeightFreeDetector()
    image = np.zeros((720, 1280, 3), np.uint8)
    image[:] = (40, 120, 50)  # grass
    cv2.line(image, (100, 200), (1200, 260), (52, 132, 62), 3)  # 12 levels brighter in every channel
    cv2.line(image, (100, 500), (1200, 560), (90, 170, 100), 3)  # 50 levels brighter
    contrast = marking_contrast(detector, image)
    w = detector.config.work_width_px
    assert contrast.shape == (round(720 * w / 1280), w)
    scale = w / 1280
    faint = contrast[int(230 * scale) - 3:int(230 * scale) + 4, int(650 * scale)].max()
    bright = contrast[int(530 * scale) - 3:int(530 * scale) + 4, int(650 * scale)].max()
    assert 10 <= faint <= 13 and 46 <= bright <= 51
    assert contrast[int(380 * scale), int(650 * scale)] == 0  # flat grass


def test_the_tallies_are_pooled_per_look_and_bin():
    bins = len(TOPHAT_CONTRAST_BINS) - 1
    rows = [{"look": "clean", "contrast_found": {"samples": [10] * bins, "found": [5] * bins}},
            {"look": "clean", "contrast_found": {"samples": [30] * bins, "found": [5] * bins}},
            {"look": "blur", "contrast_found": {"samples": [0] * bins, "found": [0] * bins}},
            {"look": "blur"}]
    table = found_by_tophat_contrast(rows)
    assert set(table) == {"clean", "blur"}
    assert table["clean"][0] == {"tophat_levels": "0-4", "samples": 40, "found_share": 0.25}
    assert table["clean"][-1]["tophat_levels"] == "40-inf"
    assert table["blur"][0]["found_share"] is None  # no samples
    assert paint_found_by_width(rows) == {}  # no row holds that tally
    assert len(PAINT_WIDTH_BINS_PX) == 9
