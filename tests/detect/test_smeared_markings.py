"""Whether a smeared frame shows a marking's band where a camera draws it (detect/smeared_markings.py)."""

from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.detect.motion_blur import motion_kernel
from broadtrack_graph.detect.smeared_markings import SmearedImage, shown_across_smear

SIZE = 200
SMEAR_PX = 20.0


def _smeared(image: np.ndarray) -> np.ndarray:
    """The image smeared along x over SMEAR_PX (a pan), with sensor noise after it."""
    smeared = cv2.filter2D(image.astype(np.float32), -1, motion_kernel(SMEAR_PX, 0.0), borderType=cv2.BORDER_REFLECT)
    noise = np.random.default_rng(3).normal(0.0, 3.0, smeared.shape)
    return np.clip(smeared + noise, 0, 255).astype(np.uint8)


def _vertical(x_px: float):
    """Samples 1 px apart down the column x_px (one run), their normal and the band's width (the smear across them)."""
    y = np.arange(20.0, 180.0)
    uv = np.column_stack([np.full(len(y), x_px), y])
    normal = np.tile([1.0, 0.0], (len(y), 1))
    return uv, np.zeros(len(y), int), normal, np.full(len(y), SMEAR_PX)


def test_a_painted_line_smeared_across_shows_as_its_band_and_nothing_else_does():
    # A 3 px line 120 levels over the grass, smeared over 20 px: a band about 18 levels over it.
    grass = np.full((SIZE, SIZE), 80.0)
    grass[:, 99:102] += 120.0
    image = SmearedImage(_smeared(grass), np.ones((SIZE, SIZE), bool), 1.0)
    checked, shown = shown_across_smear(image, *_vertical(100.0))
    assert checked.all() and shown.all()
    # Grass, and the band's own edge (a camera a band's half width across: one side lies in the band), do not show
    # (the window is whole 15 samples in from the run's ends; cut short there, the grass's noise can pass).
    for x in (140.0, 110.0, 90.0):
        checked, shown = shown_across_smear(image, *_vertical(x))
        assert checked.all() and not shown[15:-15].any()


def test_a_step_of_light_is_not_a_band_and_samples_off_the_field_are_not_checked():
    step = np.full((SIZE, SIZE), 80.0)
    step[:, 100:] += 30.0  # a mown stripe's edge: brighter on one side only
    allowed = np.ones((SIZE, SIZE), bool)
    allowed[:100, 105:] = False  # the upper half's right side is not the field
    image = SmearedImage(_smeared(step), allowed, 1.0)
    checked, shown = shown_across_smear(image, *_vertical(100.0))
    assert not shown[15:-15].any()
    assert not checked[:80].any() and checked[81:].all()  # a side off the field: no answer there (y < 100)


def test_many_samples_are_read_at_once():
    # A wide view asks tens of thousands of samples (three image values each): read in rows, not one map too wide.
    grass = np.full((SIZE, SIZE), 80.0)
    grass[:, 99:102] += 120.0
    image = SmearedImage(_smeared(grass), np.ones((SIZE, SIZE), bool), 1.0)
    uv, run, normal, band = _vertical(100.0)
    many = 80
    checked, shown = shown_across_smear(image, np.tile(uv, (many, 1)), np.repeat(np.arange(many), len(uv)),
                                        np.tile(normal, (many, 1)), np.tile(band, many))
    assert len(shown) == many * len(uv) > 12000 and checked.all() and shown.all()
