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
"""

from __future__ import annotations

import cv2
import numpy as np


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
    pieces, piece_labels, stats, _ = cv2.connectedComponentsWithStats(beyond.reshape(blobs.shape), connectivity=8)
    piece_of = piece_labels.ravel()[far_pixels]
    piece_reach = np.zeros(pieces, np.float32)
    np.maximum.at(piece_reach, piece_of, reach[far])
    cut = np.maximum(stats[:, cv2.CC_STAT_WIDTH], stats[:, cv2.CC_STAT_HEIGHT]) > longest * piece_reach
    cut[0] = False  # the background
    out = blobs.copy()
    out.ravel()[far_pixels[cut[piece_of]]] = 0
    return out
