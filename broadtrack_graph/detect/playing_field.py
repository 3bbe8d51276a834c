"""The grass and the playing field of a frame, from colour alone (the weight-free detector's first step).

Grass is an HSV range of green. The playing field is what markings and players may lie on: the grass regions
and what they enclose. Grass is looked at on cells of 4x4 working pixels, a cell being grassy when over 40 % of
its pixels are grass, and whole when at least ``whole_grass_share`` of them are grass or white (markings, a
goal's net over the grass). A connected region of grassy cells (8-connected) of at least :data:`JUDGED_CELLS`
cells belongs to the field only when ``field_min_whole_share`` of its cells are whole: mown grass is, players
leaving few cells part grass, while green seats or a green-clad crowd make a grassy region of mixed cells
(specks of other colours in every cell) and are left out. A single cell is too small to judge and is kept.
The regions kept are closed (a player or a wide line between two pieces of grass), and those covering
``field_min_area_fraction`` of the frame are filled. No I/O.
"""

from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.geometry.mask_blobs import blobs_with_stats

_CELL_PX = 4
_GRASSY_LEVEL = 100  # a cell's grass share (0-255) above which it is grassy: about 40 %
JUDGED_CELLS = 2
"""A grassy region of fewer cells (a single one) is kept unjudged: a speck of grass between posts, lines and
players, which closing joins to the field around it."""
_WHITE_HSV = ((0, 0, 160), (180, 60, 255))  # paint and nets: bright and grey, any hue
_CLOSE_KERNEL = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (7, 7))  # on cells: a gap of about 28 working px


def grass_and_field(small_bgr: np.ndarray, hue_range: tuple[int, int], min_saturation: int, min_value: int,
                    whole_grass_share: float, field_min_whole_share: float, field_min_area_fraction: float
                    ) -> tuple[np.ndarray, np.ndarray]:
    """(grass, field) uint8 masks (0/255), each (h, w) like the (h, w, 3) BGR working image (module docstring).

    Args:
        small_bgr: the frame at the working size.
        hue_range, min_saturation, min_value: grass in OpenCV's HSV (hue 0..180).
        whole_grass_share, field_min_whole_share, field_min_area_fraction: the field's rules (module docstring).
    """
    hsv = cv2.cvtColor(small_bgr, cv2.COLOR_BGR2HSV)
    grass = cv2.inRange(hsv, (hue_range[0], min_saturation, min_value), (hue_range[1], 255, 255))
    h, w = grass.shape
    share = cv2.resize(grass, (max(1, w // _CELL_PX), max(1, h // _CELL_PX)), interpolation=cv2.INTER_AREA)
    painted = cv2.bitwise_or(grass, cv2.inRange(hsv, *_WHITE_HSV))
    painted_share = cv2.resize(painted, share.shape[::-1], interpolation=cv2.INTER_AREA)
    grassy = (share > _GRASSY_LEVEL).astype(np.uint8)
    count, labels, stats, _ = blobs_with_stats(grassy)
    whole = np.bincount(labels.ravel(), weights=(painted_share >= 255 * whole_grass_share).ravel(), minlength=count)
    area = stats[:, cv2.CC_STAT_AREA]
    keep = (whole >= field_min_whole_share * area) | (area < JUDGED_CELLS)
    keep[0] = False  # the background: cells that are not grassy
    cells = cv2.morphologyEx(np.take(keep.astype(np.uint8) * 255, labels), cv2.MORPH_CLOSE, _CLOSE_KERNEL)
    contours, _ = cv2.findContours(cells, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
    filled = np.zeros_like(cells)
    big = [cnt for cnt in contours if cv2.contourArea(cnt) >= field_min_area_fraction * cells.size]
    if big:
        cv2.drawContours(filled, big, -1, 255, thickness=cv2.FILLED)
    return grass, cv2.resize(filled, (w, h), interpolation=cv2.INTER_NEAREST)
