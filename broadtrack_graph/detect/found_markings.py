"""What the weight-free detector finds in a frame before any camera is known (:class:`FoundMarkings`), the players'
legs left to find when first asked (:class:`BodiesToFeet`), and the marking map of its points. No I/O.

The players are found as bodies (:meth:`~broadtrack_graph.detect.weightfree.WeightFreeDetector.players`); running
each box on down its legs (:mod:`~broadtrack_graph.detect.player_feet`) is left until the frame's detections are first
read (:attr:`FoundMarkings.unnamed`): the markings themselves are looked for off the bodies only, so the frame's
camera-free half ends without them. Where frames are prepared ahead, the preparing side finds the legs while it is far
enough ahead to track the next frame's flow (that flow starts off the players); behind, the tracking side finds them
(:class:`~broadtrack_graph.track.ahead.FramesAhead`). Either way, the same numbers.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np

from broadtrack_graph.detect.detector import Detections
from broadtrack_graph.detect.player_feet import boxes_to_the_feet, with_legs
from broadtrack_graph.detect.point_cells import grid_thin, pixels_of, work_to_frame_px
from broadtrack_graph.detect.ridges import WideInputs


@dataclass(frozen=True)
class BodiesToFeet:
    """The players' bodies, their boxes still to run on down their legs, with what that needs.

    boxes_work_px: (P, 4) [x0, y0, x1, y1] body boxes, working pixels; body_mask: (h, w) uint8 (0 / 255) of the
    bodies; grey: (h, w) uint8 working grey image the markings were found in; grass: (h, w) uint8 grass mask;
    contrast, max_share: :func:`~broadtrack_graph.detect.player_feet.boxes_to_the_feet`'s; margin_px: the player
    mask's margin (:func:`~broadtrack_graph.detect.player_feet.with_legs`).
    """

    boxes_work_px: np.ndarray
    body_mask: np.ndarray
    grey: np.ndarray
    grass: np.ndarray
    contrast: float
    max_share: float
    margin_px: int

    def to_the_feet(self) -> tuple[np.ndarray, np.ndarray]:
        """((P, 4) boxes down to the feet, working pixels; (h, w) bool player mask with the legs)."""
        feet = boxes_to_the_feet(self.boxes_work_px, self.grey, self.grass, self.contrast, self.max_share)
        return feet, with_legs(self.body_mask, self.boxes_work_px, feet, self.margin_px) > 0


@dataclass(frozen=True)
class FaintInputs:
    """What the faint look (:func:`~broadtrack_graph.detect.faint_lines.with_faint_lines`) needs of a frame.

    colour_bgr: (h, w, 3) uint8 colour working image; allowed: (h, w) uint8, non-zero where markings may be (the
    field inside its edge, off the players' bodies); coarse: the look is taken at coarser scales too, on a frame read
    as blurred (a soft or low-resolution camera: its markings spread wider than the ridge detector's reach) or smeared
    by a pan (the markings across the smear spread over its length).
    """

    colour_bgr: np.ndarray
    allowed: np.ndarray
    coarse: bool = False


@dataclass(frozen=True)
class FoundMarkings:
    """What :meth:`~broadtrack_graph.detect.weightfree.WeightFreeDetector.find_markings` finds in a frame before any
    camera is known.

    detections: the frame's :class:`Detections` without named lines (marking points and map, players, field); while
        ``bodies`` is given, its players are the bodies' (read :attr:`unnamed`).
    points_work_px: (N, 2) sub-pixel centre-line points at the working size (what is named).
    work_size: (w, h) working size; scale: working / frame pixels; seconds: time it took.
    wide: what the wide markings' search needs when the predicted camera asks for it (None: ``wide_levels`` 0, or
        a blurred frame's, already found).
    bodies: the players' legs still to find (None: ``detections`` holds them).
    faint: what the faint look needs (None: not offered, or taken: :func:`~.faint_lines.with_faint_lines`).
    faint_look_of: the markings this faint look was taken of (None: these are not a faint look's).
    """

    detections: Detections
    points_work_px: np.ndarray
    work_size: tuple[int, int]
    scale: float
    seconds: float
    wide: WideInputs | None = None
    bodies: BodiesToFeet | None = None
    faint: FaintInputs | None = None
    faint_look_of: "FoundMarkings | None" = None

    @cached_property
    def unnamed(self) -> Detections:
        """The frame's detections without named lines, the players' boxes down to their feet and the player mask with
        their legs (found on first reading, then kept: a pickled copy carries them)."""
        if self.bodies is None:
            return self.detections
        feet, mask = self.bodies.to_the_feet()
        return replace(self.detections, player_boxes_px=(feet / self.scale) if len(feet) else feet, player_mask=mask)

    @property
    def faint_points_added(self) -> int:
        """How many points its faint look added (0: none, or these markings are not a faint look's)."""
        return 0 if self.faint_look_of is None else len(self.points_work_px) - len(self.faint_look_of.points_work_px)

    def find_legs(self) -> None:
        """Find the players' legs now: :attr:`unnamed` holds them from here on, and so does a copy sent after."""
        _ = self.unnamed


def marking_map(points: np.ndarray, size: tuple[int, int]) -> np.ndarray:
    """The marking map: the centre-line points (working pixels), one pixel wide at the working size (w, h)."""
    w, h = size
    marks = np.zeros((h, w), dtype=bool)
    pixels = pixels_of(points, size)
    marks[pixels[:, 1], pixels[:, 0]] = True
    return marks


def marked_points(points: np.ndarray, size: tuple[int, int], scale: float, spacing_px: float) -> dict:
    """A frame's detections' ``marking_mask`` and ``marking_points_px`` from its centre-line points (working pixels):
    the marking map at the working size (w, h) and the points thinned to ``spacing_px`` cells, in frame pixels
    (``scale``: working / frame pixels)."""
    return {"marking_mask": marking_map(points, size),
            "marking_points_px": work_to_frame_px(grid_thin(points, spacing_px), scale)}
