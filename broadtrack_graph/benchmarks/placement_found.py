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
SHARP_SMEAR_PX = 1.0
"""A frame the plain renderer drew with a motion blur this long or shorter (frame pixels) counts as sharp."""
SMEAR_ANGLE_TOLERANCE_DEG = 5.0
SMEAR_LENGTH_TOLERANCE_PX = 2.0
"""A smear the detector reads is the one drawn when its direction is within the first (degrees) and its length within
the second (pixels at the detector's working width) of the drawn one's."""


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


def smear_estimates(rows: list[dict], width_px: int) -> dict:
    """How the detector's motion blur (``detect.motion_blur.estimate_motion_blur``; a row's ``smear``: its length in
    frame pixels and direction) compares with the smear the plain renderer drew (its ``plain_look``): of the frames
    drawn with a smear at least the estimator's least length (``MotionBlurConfig.min_length_px``, at the working
    width), those read as drawn (:data:`SMEAR_ANGLE_TOLERANCE_DEG`, :data:`SMEAR_LENGTH_TOLERANCE_PX`), read otherwise
    and not read; of the shorter ones and of the sharp ones, those read smeared. Empty without plain rows.

    The renderer turns its kernel by ``motion_angle_deg`` with OpenCV's rotation (anticlockwise as the image is shown,
    y down): its direction in the detector's convention (degrees from +x towards +y) is ``-motion_angle_deg``.
    """
    from broadtrack_graph.detect.motion_blur import MotionBlurConfig
    from broadtrack_graph.detect.weightfree_config import REFERENCE_WIDTH_PX

    plain = [row for row in rows if "plain_look" in row]
    if not plain:
        return {}
    to_frame = width_px / REFERENCE_WIDTH_PX
    least = MotionBlurConfig().min_length_px * to_frame
    out = {"long": {"frames": 0, "as_drawn": 0, "otherwise": 0, "not_read": 0},
           "short": {"frames": 0, "read_smeared": 0}, "sharp": {"frames": 0, "read_smeared": 0}}
    for row in plain:
        drawn_px = float(row["plain_look"].get("motion_blur_px", 0.0))
        read = row.get("smear")
        group = "sharp" if drawn_px <= SHARP_SMEAR_PX else ("long" if drawn_px >= least else "short")
        out[group]["frames"] += 1
        if group != "long":
            out[group]["read_smeared"] += read is not None
        elif read is None:
            out[group]["not_read"] += 1
        else:
            drawn_deg = -float(row["plain_look"]["motion_angle_deg"])
            off_deg = abs((read["angle_deg"] - drawn_deg + 90.0) % 180.0 - 90.0)
            close = off_deg <= SMEAR_ANGLE_TOLERANCE_DEG and \
                abs(read["length_px"] - drawn_px) <= SMEAR_LENGTH_TOLERANCE_PX * to_frame
            out[group]["as_drawn" if close else "otherwise"] += 1
    return out
