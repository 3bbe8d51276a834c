"""Markings painted per pixel from distance fields: any line width, anti-aliased exactly.

A distance field holds, for every texel of the ground texture's grid, the distance (metres) from the
texel centre to the nearest marking centre line (segments, arcs, spots), clipped at
:data:`FIELD_MAX_M`. The renderer's ground hits (X, Y of every pixel) sample it bilinearly. The
share of a pixel that a marking of half width w covers is the overlap of the pixel's extent across
the marking, ``[d - s / 2, d + s / 2]`` with s the pixel's footprint across it (``|grad d|``, metres
per pixel), with ``[-w, w]``, divided by s: a box filter across the marking. A marking thinner than
a pixel is drawn faint and unbroken, one many pixels wide with sharp edges; the line width is a
free parameter of every frame, not baked into a texture.

Pitch frame: metres, origin at the centre spot, z down; fields are (rows, cols) float32 on the grid
of :class:`GroundGrid`. No I/O here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import cv2
import numpy as np

from broadtrack_graph.geometry.pitch import Arc, PitchTemplate, Segment
from broadtrack_graph.synth.texture import TextureSet

FIELD_MAX_M = 1.5
"""Distances are clipped here (metres): pixels this far from every marking are never painted."""

SPOT_RADIUS_M = 0.11
"""Radius of the centre spot and the penalty marks (metres), at the nominal line half width."""

NOMINAL_HALF_WIDTH_M = 0.06
"""Half the width of a regulation marking (12 cm); spots grow and shrink with the line width around it."""

CORNER_ARC_RADIUS_M = 1.0
"""Radius of the corner arcs (painted on every pitch, not a SoccerNet class)."""


@dataclass(frozen=True)
class GroundGrid:
    """The texel grid of the ground texture (metres): texel (col, row) is centred at
    (x_min + (col + 0.5) texel, y_min + (row + 0.5) texel)."""

    x_min_m: float
    y_min_m: float
    texel_m: float
    rows: int
    cols: int

    @classmethod
    def of(cls, textures: TextureSet) -> "GroundGrid":
        """The grid of a texture set's ground texture."""
        rows, cols = textures.class_ids.shape
        return cls(float(textures.x_min_m), float(textures.y_min_m), float(textures.texel_m), int(rows), int(cols))

    def texel_coordinates(self, X: np.ndarray, Y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(H, W) float32 metres -> (H, W) float32 texel coordinates for ``cv2.remap``."""
        scale = 1.0 / self.texel_m
        map_x = cv2.transform(X, np.array([[scale, -self.x_min_m * scale - 0.5]]))
        map_y = cv2.transform(Y, np.array([[scale, -self.y_min_m * scale - 0.5]]))
        return map_x, map_y


@dataclass(frozen=True)
class Strokes:
    """Marking centre lines (metres, pitch frame, ground plane).

    segments: (K, 4) [x0, y0, x1, y1]; arcs: (M, 5) [cx, cy, radius, from_rad, to_rad] counter-clockwise;
    spots: (P, 3) [x, y, radius at the nominal half width].
    """

    segments: np.ndarray
    arcs: np.ndarray
    spots: np.ndarray


def pitch_strokes(pitch: PitchTemplate | None = None) -> Strokes:
    """The painted markings of a pitch: every ground class, the corner arcs, the centre spot and the penalty marks."""
    pitch = pitch or PitchTemplate()
    segments, arcs = [], []
    for name, element in pitch.elements.items():
        if not pitch.is_on_ground(name):
            continue
        if isinstance(element, Segment):
            segments.append([element.start_w[0], element.start_w[1], element.end_w[0], element.end_w[1]])
        elif isinstance(element, Arc):
            arcs.append([element.centre_w[0], element.centre_w[1], element.radius_m, element.from_rad, element.to_rad])
    half_l, half_w = pitch.dimensions.length_m / 2, pitch.dimensions.width_m / 2
    for sx in (-1.0, 1.0):
        for sy in (-1.0, 1.0):
            start = math.atan2(-sy, -sx) - math.pi / 4  # the quarter facing into the pitch
            arcs.append([sx * half_l, sy * half_w, CORNER_ARC_RADIUS_M, start, start + math.pi / 2])
    spots = [[*pitch.keypoints[name][:2], SPOT_RADIUS_M]
             for name in ("Centre spot", "Left penalty mark", "Right penalty mark")]
    return Strokes(np.asarray(segments, float).reshape(-1, 4), np.asarray(arcs, float).reshape(-1, 5),
                   np.asarray(spots, float).reshape(-1, 3))


def _window(grid: GroundGrid, x0: float, x1: float, y0: float, y1: float, margin: float):
    """Texel index slices and texel centre coordinates (1-D) of a world box grown by margin; None when off the grid."""
    c0 = max(0, int(math.floor((x0 - margin - grid.x_min_m) / grid.texel_m)))
    c1 = min(grid.cols, int(math.ceil((x1 + margin - grid.x_min_m) / grid.texel_m)) + 1)
    r0 = max(0, int(math.floor((y0 - margin - grid.y_min_m) / grid.texel_m)))
    r1 = min(grid.rows, int(math.ceil((y1 + margin - grid.y_min_m) / grid.texel_m)) + 1)
    if c1 <= c0 or r1 <= r0:
        return None
    xs = (grid.x_min_m + (np.arange(c0, c1) + 0.5) * grid.texel_m).astype(np.float32)[None, :]
    ys = (grid.y_min_m + (np.arange(r0, r1) + 0.5) * grid.texel_m).astype(np.float32)[:, None]
    return (slice(r0, r1), slice(c0, c1)), xs, ys


def distance_field(grid: GroundGrid, strokes: Strokes) -> np.ndarray:
    """(rows, cols) float32: metres from each texel centre to the nearest stroke, clipped at FIELD_MAX_M.

    Each stroke updates only the texels of its bounding box grown by FIELD_MAX_M. A spot of radius r counts
    as a point grown by ``r - NOMINAL_HALF_WIDTH_M``, so it is r wide at the nominal line width.
    """
    max_m = FIELD_MAX_M
    field = np.full((grid.rows, grid.cols), np.float32(max_m), np.float32)
    for x0, y0, x1, y1 in strokes.segments:
        window = _window(grid, min(x0, x1), max(x0, x1), min(y0, y1), max(y0, y1), max_m)
        if window is None:
            continue
        where, xs, ys = window
        ex, ey = np.float32(x1 - x0), np.float32(y1 - y0)
        length2 = max(float(ex * ex + ey * ey), 1e-12)
        px, py = xs - np.float32(x0), ys - np.float32(y0)
        t = np.clip((px * ex + py * ey) / np.float32(length2), 0.0, 1.0)
        np.minimum(field[where], np.hypot(px - t * ex, py - t * ey), out=field[where])
    for cx, cy, radius, from_rad, to_rad in strokes.arcs:
        window = _window(grid, cx - radius, cx + radius, cy - radius, cy + radius, max_m)
        if window is None:
            continue
        where, xs, ys = window
        px, py = xs - np.float32(cx), ys - np.float32(cy)
        rho = np.hypot(px, py)
        span = to_rad - from_rad
        d = np.abs(rho - np.float32(radius))
        if span < 2 * math.pi - 1e-9:
            inside = np.mod(np.arctan2(py, px) - np.float32(from_rad), np.float32(2 * math.pi)) <= np.float32(span)
            ends = [(cx + radius * math.cos(a), cy + radius * math.sin(a)) for a in (from_rad, to_rad)]
            to_end = np.minimum(*(np.hypot(xs - np.float32(ex), ys - np.float32(ey)) for ex, ey in ends))
            d = np.where(inside, d, to_end)
        np.minimum(field[where], d, out=field[where])
    for x, y, radius in strokes.spots:
        grow = radius - NOMINAL_HALF_WIDTH_M
        window = _window(grid, x, x, y, y, max_m + grow)
        if window is None:
            continue
        where, xs, ys = window
        d = np.maximum(np.hypot(xs - np.float32(x), ys - np.float32(y)) - np.float32(grow), 0.0)
        np.minimum(field[where], d, out=field[where])
    np.minimum(field, np.float32(max_m), out=field)
    return field


@lru_cache(maxsize=2)
def marking_field(grid: GroundGrid) -> np.ndarray:
    """The distance field of the regulation markings (:func:`pitch_strokes`) on a grid (cached; do not modify)."""
    field = distance_field(grid, pitch_strokes())
    field.setflags(write=False)
    return field


def lookup(field: np.ndarray, map_x: np.ndarray, map_y: np.ndarray) -> np.ndarray:
    """(H, W) float32 distances (metres) at texel coordinates (bilinear; FIELD_MAX_M off the grid)."""
    return cv2.remap(field, map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=FIELD_MAX_M)


def footprint(distance_m: np.ndarray) -> np.ndarray:
    """(H, W) float32 metres per pixel across the nearest marking: ``|grad d|`` from one-sided differences.

    The larger of the two one-sided differences along each image axis is used, so a pixel on the
    ridge of the field (the marking's centre line, where d turns) still sees the true slope.
    """
    d = np.ascontiguousarray(distance_m, dtype=np.float32)
    slopes = []
    for axis in (1, 0):
        f = np.zeros_like(d)
        if d.shape[axis] > 1:
            ahead = d[:, 1:] if axis == 1 else d[1:]
            behind = d[:, :-1] if axis == 1 else d[:-1]
            step = cv2.absdiff(ahead, behind)
            if axis == 1:
                f[:, 0], f[:, -1] = step[:, 0], step[:, -1]
                cv2.max(step[:, 1:], step[:, :-1], dst=f[:, 1:-1])
            else:
                f[0], f[-1] = step[0], step[-1]
                cv2.max(step[1:], step[:-1], dst=f[1:-1])
        slopes.append(f)
    return cv2.magnitude(*slopes)


MAX_HALF_WIDTH_M = 0.4
"""Widest half width :func:`coverage` paints (beyond it a pixel at the clip distance could be painted)."""


def coverage(distance_m: np.ndarray, half_width_m: float) -> np.ndarray:
    """(H, W) float32 in [0, 1]: the share of each pixel a marking of half width half_width_m (metres) covers.

    Args:
        distance_m: (H, W) float32 distances to the marking's centre line (:func:`lookup`), clipped at FIELD_MAX_M.
        half_width_m: half the painted width, metres, below MAX_HALF_WIDTH_M.

    Note:
        A pixel at the clip distance is never painted: its footprint is at most sqrt(2) FIELD_MAX_M (both
        one-sided differences of a field in [0, FIELD_MAX_M]), so its extent ends beyond the half width.
    """
    if not 0.0 < half_width_m < MAX_HALF_WIDTH_M:
        raise ValueError(f"half_width_m must be in (0, {MAX_HALF_WIDTH_M}) m, got {half_width_m}")
    d = np.ascontiguousarray(distance_m, dtype=np.float32)
    s = cv2.max(footprint(d), 1e-4)
    half_s = cv2.multiply(s, 0.5)
    lo = cv2.max(cv2.subtract(d, half_s), -float(half_width_m))
    hi = cv2.min(cv2.add(d, half_s), float(half_width_m))
    alpha = cv2.divide(cv2.subtract(hi, lo), s)
    return cv2.min(cv2.max(alpha, 0.0), 1.0)
