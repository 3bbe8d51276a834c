"""Players' blobs apart from the markings they stand on. No I/O.

The weight-free detector finds players as the non-grass blobs that survive an opening wider than a line
(:meth:`~broadtrack_graph.detect.weightfree.WeightFreeDetector.players`). In a zoomed view a marking is wider than
that opening: a player standing on it joins it into one blob, which is then either taken for one player whose mask
hides the marking along its whole length (no ridge is looked for there), or, too tall and narrow for a body, not taken
at all (the player is lost). :func:`bodies_apart_from_markings` cuts such pieces off each blob by the blob's own scale:

* a blob's **body** is its core, the pixels at least ``core_share`` of the blob's greatest distance ``D`` to its edge
  (a body's half width), grown back by ``D``. A marking is narrower than the body standing on it (a 12 cm line
  beside a 40-50 cm torso: about a quarter of its width), so the core leaves it out;
* what lies beyond the body is cut off where it runs on for more than ``longest`` ``D`` (a marking crossing the
  frame); shorter pieces stay (legs, arms, a ball at the feet).

A blob of a marking alone keeps its whole width as its core: it is not changed (the detector's shape test drops it).

A marking only a little wider than the opening survives it where it is widest: a row of short pieces along it, each
small and upright enough to pass for a distant player, whose masks then hide the marking there (a zoomed view's
circle, a low camera's near lines). :func:`marking_pieces` tells them from bodies: before the opening they are joined
by the marking's narrower stretches into a blob far longer than themselves, and they are at most twice as deep as
what joins them (depths are a pixel or two at half the working width: a stretch 3 px wide is about 2 deep, one 2 px
wide 1), where a body is deeper than the legs, the marking or the other bodies it is joined to. A distant player
only 3-4 px wide standing on a marking can pass for a piece: its box is lost, and its mask, which hides little.
"""

from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.geometry.mask_blobs import blobs_with_stats


def bodies_apart_from_markings(blobs: np.ndarray, core_share: float = 0.4, longest: float = 4.0) -> np.ndarray:
    """The blobs with the long thin pieces joined to a thicker body cut off (module docstring).

    Args:
        blobs: (h, w) uint8 mask, 255 on the blobs (any size; distances in its pixels).
        core_share: a body's core: its pixels at least this share of the blob's greatest distance to its edge.
        longest: a piece beyond the body longer than this many of that distance (its box's longer side) is cut.

    Returns:
        (h, w) uint8 mask, 255 on what stays of the blobs.
    """
    count, labels = cv2.connectedComponents(blobs, connectivity=8)
    if count <= 1:
        return blobs
    inside = np.flatnonzero(blobs)  # the blobs' pixels (flat indices): the few the sums below run over
    depth = cv2.distanceTransform(blobs, cv2.DIST_L2, 3).ravel()[inside]
    deepest = np.zeros(count, np.float32)
    blob_of = labels.ravel()[inside]
    np.maximum.at(deepest, blob_of, depth)
    reach = deepest[blob_of]  # each pixel's blob's greatest depth: the body's half width
    not_core = np.full(blobs.size, 255, np.uint8)
    not_core[inside[depth >= core_share * reach]] = 0
    to_core = cv2.distanceTransform(not_core.reshape(blobs.shape), cv2.DIST_L2, 3).ravel()[inside]
    far = to_core > reach
    if not far.any():
        return blobs
    far_pixels = inside[far]
    beyond = np.zeros(blobs.size, np.uint8)
    beyond[far_pixels] = 1
    pieces, piece_labels, stats, _ = blobs_with_stats(beyond.reshape(blobs.shape))
    piece_of = piece_labels.ravel()[far_pixels]
    piece_reach = np.zeros(pieces, np.float32)
    np.maximum.at(piece_reach, piece_of, reach[far])
    cut = np.maximum(stats[:, cv2.CC_STAT_WIDTH], stats[:, cv2.CC_STAT_HEIGHT]) > longest * piece_reach
    cut[0] = False  # the background
    out = blobs.copy()
    out.ravel()[far_pixels[cut[piece_of]]] = 0
    return out


def marking_pieces(opened: np.ndarray, labels: np.ndarray, stats: np.ndarray, unopened: np.ndarray,
                   asked: np.ndarray, min_length_ratio: float = 3.0, max_depth_ratio: float = 2.0,
                   reach_px: int = 3) -> np.ndarray:
    """Which blobs left by the opening are pieces of a marking wider than it, not bodies (module docstring).

    Args:
        opened: (h, w) uint8 mask after the opening (255 on the blobs); labels, stats: its
            cv2.connectedComponentsWithStats, (h, w) int32 labels (0: the background) and (K + 1, 5) boxes and areas.
        unopened: (h, w) uint8 mask before the opening, the same size.
        asked: (K,) bool, the blobs to look at (the others are not pieces).
        min_length_ratio: a piece's blob before the opening is at least this many times as long as the piece (the
            longer sides of their boxes) ...
        max_depth_ratio: ... the piece is at most this many times as deep (the greatest distance to the blob's edge)
            as what joins it there, the blob's pixels off every piece within ``reach_px`` of it ...
            and at most two arms of its blob leave it there (:func:`_arms`).

    Returns:
        (K,) bool, for labels 1 .. K.
    """
    count = len(stats)
    pieces = np.zeros(count, bool)
    if not asked.any():
        return pieces[1:]
    _, blob_labels, blob_stats, _ = blobs_with_stats(unopened)
    cols, rows = cv2.findNonZero(opened).reshape(-1, 2).T
    piece_of = labels[rows, cols]  # the pieces' pixels: the few the sums below run over
    blob_of_piece = np.zeros(count, np.int64)
    blob_of_piece[piece_of] = blob_labels[rows, cols]  # the opening only takes pixels away: one blob each

    def box_length(s: np.ndarray) -> np.ndarray:
        return np.maximum(s[:, cv2.CC_STAT_WIDTH], s[:, cv2.CC_STAT_HEIGHT])

    short = np.r_[False, asked] & (box_length(blob_stats)[blob_of_piece] >= min_length_ratio * box_length(stats))
    if not short.any():
        return pieces[1:]
    # What follows looks only around the short pieces: the box holding them, reach_px and a pixel more around.
    x, y, w, h = (stats[short, k] for k in range(4))
    pad = reach_px + 2
    x0, y0 = max(int(x.min()) - pad, 0), max(int(y.min()) - pad, 0)
    x1, y1 = min(int((x + w).max()) + pad, labels.shape[1]), min(int((y + h).max()) + pad, labels.shape[0])
    window = (slice(y0, y1), slice(x0, x1))
    around = cv2.copyMakeBorder(unopened[window], 1, 1, 1, 1, cv2.BORDER_REPLICATE)  # the blobs run on past it
    depth = cv2.distanceTransform(around, cv2.DIST_L2, cv2.DIST_MASK_3)[1:-1, 1:-1]
    inside = (rows >= y0) & (rows < y1) & (cols >= x0) & (cols < x1)
    rows, cols, piece_of = rows[inside] - y0, cols[inside] - x0, piece_of[inside]
    joins = depth.copy()
    joins[rows, cols] = 0.0
    side = 2 * reach_px + 1
    joins_near = cv2.dilate(joins, cv2.getStructuringElement(cv2.MORPH_RECT, (side, side)))
    piece_depth = np.zeros(count, np.float32)
    np.maximum.at(piece_depth, piece_of, depth[rows, cols])
    joined_depth = np.zeros(count, np.float32)
    np.maximum.at(joined_depth, piece_of, joins_near[rows, cols])
    pieces = short & (piece_depth <= max_depth_ratio * joined_depth)
    if pieces.any():
        pieces &= _arms(labels[window], pieces, unopened[window], reach_px) <= 2
    return pieces[1:]


def _arms(labels: np.ndarray, asked: np.ndarray, unopened: np.ndarray, reach_px: int) -> np.ndarray:
    """(K + 1,) how many separate arms of its blob leave each asked piece (``asked``: (K + 1,) bool by label): the
    blob's pieces of a ring from 2 to ``reach_px`` pixels around the piece (0 where not asked). A marking's stretch
    runs on at its two ends; a goal net's knot, where four strands meet, has four (so has a crossing of markings)."""
    piece_labels = np.where(asked[labels], labels, 0)
    near = cv2.dilate((piece_labels > 0).astype(np.uint8), np.ones((3, 3), np.uint8))
    side = 2 * reach_px + 1
    reach = cv2.dilate(piece_labels.astype(np.float32), np.ones((side, side), np.uint8))  # the nearby piece's label
    ring = ((reach > 0) & (near == 0) & (unopened > 0)).astype(np.uint8)
    count, ring_labels = cv2.connectedComponents(ring, connectivity=8)
    if count <= 1:
        return np.zeros(len(asked), np.int64)
    cols, rows = cv2.findNonZero(ring).reshape(-1, 2).T
    piece_of_arm = np.zeros(count, np.int64)
    np.maximum.at(piece_of_arm, ring_labels[rows, cols], reach[rows, cols].astype(np.int64))
    return np.bincount(piece_of_arm[1:], minlength=len(asked))[:len(asked)]


def centres_inside(field: np.ndarray, stats: np.ndarray, size: tuple[int, int], margin_px: int) -> np.ndarray:
    """(K,) whether each blob's box centre (``stats``' rows 1..K, at ``size`` (w, h)) lies at least ``margin_px``
    (pixels of that size) inside ``field`` (uint8, non-zero inside, any size; the image's border is no edge)."""
    w, h = size
    side = 2 * margin_px + 1
    inner = cv2.erode(cv2.resize(field, (w, h), interpolation=cv2.INTER_NEAREST),
                      cv2.getStructuringElement(cv2.MORPH_RECT, (side, side)))
    cols = np.clip(stats[1:, cv2.CC_STAT_LEFT] + stats[1:, cv2.CC_STAT_WIDTH] // 2, 0, w - 1)
    rows = np.clip(stats[1:, cv2.CC_STAT_TOP] + stats[1:, cv2.CC_STAT_HEIGHT] // 2, 0, h - 1)
    return inner[rows, cols] > 0


def upright_bodies(opened: np.ndarray, unopened: np.ndarray, field: np.ndarray, min_area_px: int,
                   boundary_margin_px: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The blobs the players' opening leaves that are bodies: upright, large enough, and not a marking's pieces.

    Args:
        opened: (h, w) uint8 mask after the opening (and :func:`bodies_apart_from_markings`), 255 on the blobs.
        unopened: (h, w) uint8 mask before the opening.
        field: uint8 map of the playing field (non-zero inside; any size of the same aspect ratio).
        min_area_px: a body's least area in pixels at twice this mask's size (the working size: it is found at half).
        boundary_margin_px: a marking's piece is one only this far inside the field (pixels at twice this size; a
            crowd's specks along the field's edge are no marking's: they stay bodies, their masks hide no paint).

    Returns:
        labels: (h, w) int32 labels of ``opened`` (0: the background); stats: (K + 1, 5) their boxes and areas
        (``cv2.CC_STAT_*``); body: (K,) bool for labels 1 .. K.
    """
    _, labels, stats, _ = blobs_with_stats(opened)
    body = upright_shapes(stats, min_area_px)
    pieces = marking_pieces(opened, labels, stats, unopened, body)  # a wide marking's widest stretches
    if pieces.any():
        body &= ~(pieces & centres_inside(field, stats, unopened.shape[::-1], boundary_margin_px))
    return labels, stats, body


def upright_shapes(stats: np.ndarray, min_area_px: int) -> np.ndarray:
    """(K,) whether each blob (``stats``' rows 1..K, found at half the working size) has a body's shape: upright (its
    box 0.8-6 times as tall as wide), filling a quarter of its box, and at least ``min_area_px`` at the working size."""
    _, _, bw, bh, area = (stats[1:, i] for i in range(5))
    return (4 * area >= min_area_px) & (bh >= 0.8 * bw) & (bh <= 6 * bw) & (area >= 0.25 * bw * bh)
