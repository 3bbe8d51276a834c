"""Marking-mask PNGs of a detections file: 255 on markings, MASK_FIELD_VALUE on the rest of the playing field, 0 elsewhere."""

from __future__ import annotations

import logging
from pathlib import Path

import cv2
import numpy as np

log = logging.getLogger(__name__)


MASK_FIELD_VALUE = 64
"""Grey level of playing-field pixels (no marking) in the written mask PNGs."""


def mask_image(marking_mask: np.ndarray, field_mask: np.ndarray | None = None) -> np.ndarray:
    """The uint8 PNG content of a frame's mask: 255 markings, MASK_FIELD_VALUE field, 0 elsewhere.

    Args:
        marking_mask: (h, w) bool (any working size).
        field_mask: (h', w') bool playing surface or None; resized (nearest) to (h, w).
    """
    out = np.zeros(marking_mask.shape, np.uint8)
    if field_mask is not None:
        if field_mask.shape != marking_mask.shape:
            field_mask = cv2.resize(field_mask.astype(np.uint8), marking_mask.shape[::-1],
                                    interpolation=cv2.INTER_NEAREST) > 0
        out[field_mask] = MASK_FIELD_VALUE
    out[marking_mask] = 255
    return out


def read_mask_png(path: Path, width_px: int, height_px: int) -> tuple[np.ndarray, np.ndarray | None] | None:
    """A marking mask image of a detections file, at (W, H): (markings, field or None).

    Markings are pixels above 127; when the image also has pixels in 1..127 they mark the
    playing surface (``detect`` writes 255 on markings, 64 on the rest of the field).
    None (with a warning) when the image cannot be read.
    """
    grey = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
    if grey is None:
        log.warning("%s: marking mask cannot be read; ignored", path)
        return None
    if grey.shape != (height_px, width_px):
        grey = cv2.resize(grey, (width_px, height_px), interpolation=cv2.INTER_NEAREST)
    markings = grey > 127
    has_field = bool(np.any((grey > 0) & (grey <= 127)))
    return markings, (grey > 0) if has_field else None


def write_mask_png(path: str | Path, marking_mask: np.ndarray, field_mask: np.ndarray | None = None) -> bool:
    """Write a frame's marking mask PNG (see :func:`mask_image`); False (with a warning) when it cannot be written."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    if cv2.imwrite(str(path), mask_image(marking_mask, field_mask), [cv2.IMWRITE_PNG_COMPRESSION, 3]):
        return True
    log.warning("%s: cannot write the marking mask; the record has none", path)
    return False
