from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.benchmarks.placement_found import (
    PAINT_WIDTH_BINS_PX,
    TOPHAT_CONTRAST_BINS,
    found_by_tophat_contrast,
    marking_contrast,
    paint_found_by_width,
    smear_estimates,
)
from broadtrack_graph.benchmarks.placement_frames import draw_frame
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


def test_the_smears_read_are_counted_against_the_smears_drawn():
    def row(drawn_px, angle_deg=0.0, read=None):
        out = {"plain_look": {"motion_blur_px": drawn_px, "motion_angle_deg": angle_deg}}
        if read is not None:
            out["smear"] = {"length_px": read[0], "angle_deg": read[1]}
        return out

    # at 1920 px the estimator's least length (9 px at 960) is 18 px, the length tolerance 4 px
    rows = [row(24, 30.0, (25.0, 152.0)),  # drawn at -30 deg: read as drawn (2 deg, 1 px off)
            row(24, 30.0, (24.0, 30.0)),  # the mirror direction: read otherwise
            row(30, 90.0, (20.0, 90.0)),  # 10 px short: otherwise
            row(20, 10.0),  # not read
            row(12, 0.0, (12.0, 0.0)),  # shorter than the estimator reads: read smeared
            row(0), row(0, read=(20.0, 45.0)), {"look": "clean"}]
    assert smear_estimates(rows, 1920) == {"long": {"frames": 4, "as_drawn": 1, "otherwise": 2, "not_read": 1},
                                           "short": {"frames": 1, "read_smeared": 1},
                                           "sharp": {"frames": 2, "read_smeared": 1}}
    assert smear_estimates([{"look": "clean"}], 1920) == {}


def test_a_smear_the_plain_renderer_draws_is_read_in_its_direction():
    # Frame 70 of seed 3 (plain): a motion blur of 24 px at 1280 px, which the estimator reads
    frame = draw_frame(3, 70, 1280, 720, ["clean"], "plain")
    blur = WeightFreeDetector().detect(frame["image"]).motion_blur
    look = frame["look"]
    row = {"plain_look": {"motion_blur_px": look.motion_blur_px, "motion_angle_deg": look.motion_angle_deg},
           "smear": {"length_px": blur.length_px, "angle_deg": blur.angle_deg}}
    assert look.motion_blur_px >= 20 and smear_estimates([row], 1280)["long"]["as_drawn"] == 1
