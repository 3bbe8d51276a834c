"""Maps a frame's camera confidence derives from its detections, made once and asked again for each camera compared
(:mod:`.confidence`): the field without the band along its outer edge, and the marking map's pieces long enough to be
painted lines. No I/O.

Each keeps the last map it was asked about (the same array asked again gets the same answer without the work): the
cameras of one frame are all compared with the same maps.
"""

from __future__ import annotations

import cv2
import numpy as np


def _remembered(slot: list, source: np.ndarray, setting: float, make) -> np.ndarray:
    """``make()`` (a map, made read only), or the one ``slot`` holds when it was made from this very ``source`` array
    at this ``setting``. The slot holds the source too: its id is not reused while it is remembered."""
    last = slot[0] if slot else None
    if last is not None and last[0] is source and last[1] == setting:
        return last[2]
    made = make()
    made.setflags(write=False)
    slot[:] = [(source, setting, made)]
    return made


_LAST_INSIDE_EDGE: list = []  # [(field map, margin, the map inside its edge band)]: the last one asked


def inside_field_edge(field: np.ndarray, margin_px: int) -> np.ndarray:
    """The field map without the band ``margin_px`` wide along its outer edge, as the weight-free detector's
    ridges are kept (its outline filled: players' holes do not widen the band; the image border is not an edge).

    Args:
        field: (h, w) bool field map.
        margin_px: the band's width (pixels of the map; a disc's reach); 0: the map as it is.

    Returns:
        (h, w) bool, read only. The same array while the same map (the same array) is asked again: a frame's
        cameras are all compared with one map.
    """
    if margin_px <= 0:
        return field
    return _remembered(_LAST_INSIDE_EDGE, field, margin_px, lambda: _inside_edge(field, margin_px))


def _inside_edge(field: np.ndarray, margin_px: int) -> np.ndarray:
    outline = np.zeros(field.shape, np.uint8)
    contours, _ = cv2.findContours(field.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    cv2.drawContours(outline, contours, -1, 1, thickness=cv2.FILLED)
    disc = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * margin_px + 1, 2 * margin_px + 1))
    return field & (cv2.erode(outline, disc) > 0)


_LAST_LONG_PIECES: list = []  # [(marking map, length, its long pieces)]: the last one asked


def long_pieces(marks: np.ndarray, min_length_px: float) -> np.ndarray:
    """The pixels of a marking map that belong to a piece (8-connected) at least ``min_length_px`` long: its bounding
    box's longer side. A painted line, even broken by a player or faint paint, leaves pieces of tens of pixels; the
    grass's texture, seen at a grazing angle, leaves specks a few pixels long that pass the detector's ridge test one
    by one.

    Args:
        marks: (h, w) bool marking map (one pixel wide centre lines).
        min_length_px: pixels of the map; 0 or less: the map as it is.

    Returns:
        (h, w) bool, read only. The same array while the same map (the same array) is asked again.
    """
    if min_length_px <= 0:
        return marks
    return _remembered(_LAST_LONG_PIECES, marks, min_length_px, lambda: _long_pieces(marks, min_length_px))


def _long_pieces(marks: np.ndarray, min_length_px: float) -> np.ndarray:
    # The pieces' extents from their pixels alone (the map is sparse: OpenCV's statistics would visit every pixel).
    grid = np.ascontiguousarray(marks, dtype=np.uint8)
    _, labels = cv2.connectedComponents(grid, connectivity=8)
    pieces = np.zeros(marks.shape, bool)
    found = cv2.findNonZero(grid)
    if found is not None:
        cols, rows = found.reshape(-1, 2).T
        order = np.argsort(labels[rows, cols], kind="stable")  # each piece's pixels together
        rows, cols, owner = rows[order], cols[order], labels[rows[order], cols[order]]
        starts = np.flatnonzero(np.concatenate([[True], owner[1:] != owner[:-1]]))
        extent = np.maximum(*(np.maximum.reduceat(v, starts) - np.minimum.reduceat(v, starts) + 1
                              for v in (rows, cols)))
        pieces[rows, cols] = np.repeat(extent >= min_length_px, np.diff(np.append(starts, len(owner))))
    return pieces
