"""How much of the true cameras' template the detector finds, by a property of each marking: the tallies of
``bench placements --random`` (:mod:`.random_placements`). No I/O.

Each frame's row holds, for one property, the true camera's template samples in each bin of it and how many of them
the detector's marking map shows (``reinit.template_reach.found_by_paint_width`` and its kin); the report pools the
rows: per bin, the samples and the share found. The bins say where the detector's reach ends: a painted width it no
longer resolves, a smear that leaves too little contrast, paint too faint against the grass.
"""

from __future__ import annotations

import cv2
import numpy as np

PAINT_WIDTH_BINS_PX = (0.0, 0.1, 0.15, 0.2, 0.3, 0.4, 0.6, 1.0, float("inf"))
"""Bins of the painted width (working pixels) the detector's finds on the true cameras are counted in."""
SMEARED_CONTRAST_BINS = (0.0, 0.025, 0.05, 0.075, 0.1, 0.15, 0.2, 0.3, 0.5, float("inf"))
"""Bins of the share of contrast a frame's motion blur leaves a marking (``reinit.confidence.smeared_contrast``)."""
TOPHAT_CONTRAST_BINS = (0.0, 4.0, 8.0, 11.0, 14.0, 20.0, 40.0, float("inf"))
"""Bins of a marking's contrast on the detector's top-hat (grey levels over the ground around it, working image)."""


def marking_contrast(detector, image_bgr: np.ndarray) -> np.ndarray:
    """(h, w) uint8: the white top-hat of the weight-free detector's working marking channel (its
    ``working_images``, the top-hat of its ``tophat_kernel_px``): the contrast of each pixel over the ground around
    it that its ridge step thresholds (before a frame's smear is undone, ``detect.motion_blur``)."""
    _, grey, _ = detector.working_images(image_bgr)
    k = detector.config.tophat_kernel_px
    return cv2.morphologyEx(grey, cv2.MORPH_TOPHAT, cv2.getStructuringElement(cv2.MORPH_RECT, (k, k)))


def smear_found_by_contrast(rows: list[dict]) -> list[dict]:
    """The frames found smeared, pooled: each smeared-contrast bin's true-camera template samples and the share of
    them found (rows with a ``smear_found`` entry)."""
    counts = [row["smear_found"] for row in rows if "smear_found" in row]
    return _found_shares(counts, SMEARED_CONTRAST_BINS, "contrast") if counts else []


def paint_found_by_width(rows: list[dict]) -> dict:
    """Per look: each painted-width bin's true-camera template samples and the share of them found (rows with a
    ``paint_found`` entry)."""
    return _by_look(rows, "paint_found", PAINT_WIDTH_BINS_PX, "paint_px")


def found_by_tophat_contrast(rows: list[dict]) -> dict:
    """Per look: each top-hat contrast bin's true-camera template samples and the share of them found (rows with a
    ``contrast_found`` entry)."""
    return _by_look(rows, "contrast_found", TOPHAT_CONTRAST_BINS, "tophat_levels")


def _by_look(rows: list[dict], entry: str, bins, key: str) -> dict:
    """:func:`_found_shares` of the rows' ``entry`` counts, per look (the rows holding one)."""
    return {look: _found_shares([row[entry] for row in rows if row["look"] == look and entry in row], bins, key)
            for look in sorted({row["look"] for row in rows if entry in row})}


def _found_shares(counts: list[dict], bins, key: str) -> list[dict]:
    """Per bin of ``bins`` (named ``key``): the samples of the rows' ``counts`` ({"samples", "found"}, one list
    each) pooled, and the share of them found."""
    samples, found = np.sum([c["samples"] for c in counts], axis=0), np.sum([c["found"] for c in counts], axis=0)
    return [{key: f"{lo:g}-{hi:g}", "samples": int(n), "found_share": round(float(k) / n, 3) if n else None}
            for lo, hi, n, k in zip(bins[:-1], bins[1:], samples, found)]
