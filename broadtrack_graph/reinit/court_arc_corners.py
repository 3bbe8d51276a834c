"""Court-model hypotheses from a circle's arc and two straight markings of the pitch's two directions, by rectifying
the ground. No I/O.

A penalty arc seen with the far touchline and the halfway line, its 16.5 m line out of view, has no line across it:
the circle tiers (:mod:`.court_circle`, :mod:`.court_arcs`) ask for one. One line beside the arc leaves the rectified
valley of :mod:`.court_arcs` free along f (almost any pitch line fits somewhere on it); two lines of the two
directions do not: on the ground they meet at a right angle, and each lies at its own distance from the circle's
centre. For a focal length ``f``, a tilt and a roll (principal point at the image centre, pan 0, 1 m up;
:func:`~.court_arcs.rectifiers`) the arc's points are put on the ground and a circle fitted to them, and the two
lines are put there too. The error of a place, for an arc, a pair of lines and a pitch corner (a circle with a
line ``x = c`` and a line ``y = c``: :func:`circle_corners`), is the root mean square of the arc's points off their
circle, the cosine of the lines' angle and each line's distance from the centre off the corner's (all in radii).
Every place of a grid is tried at once, and the best pairings are narrowed in f, tilt and roll together
(Levenberg-Marquardt, every pairing at once). Which way round the lines lie about the centre (the corner's
handedness) and the side of a penalty arc's own 16.5 m line its painted arc lies on are asked too. The circle's
radius gives the height, its centre and the lines' feet place and turn the camera, and the homographies join the
gate, map score and fits of every hypothesis.

Image coordinates are normalised as in :mod:`.court_lines`: ``x_n = (u - W / 2) / s``, ``s = W / 2``. Pitch frame:
SoccerNet (metres, origin at the centre spot, z down).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.detect.marking_structures import ImageLine
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.court_arcs import (
    narrowed,
    pieces_of,
    placed_homographies,
    rectified,
    rectifiers,
)
from broadtrack_graph.reinit.court_circle import CircleChord


@dataclass(frozen=True)
class ArcCornerConfig:
    """Settings of :func:`arc_corner_homographies`."""

    max_line_share: float = 5.0  # a corner's lines pass within this many radii of its circle's centre
    max_lines: int = 6  # the longest straight markings paired (every ordered pair of two of them)
    focal_steps: int = 14  # f / s on a geometric grid over the focal range ...
    tilt_range_deg: tuple[float, float] = (30.0, 89.5)  # ... and the tilt on an even grid (roll 0)
    tilt_steps: int = 20
    max_pairings: int = 8  # the arc, line pair and corner pairings whose best place errs least ...
    coarse_max_error: float = 0.3  # ... and at most this (radii, root mean square), narrowed
    max_error: float = 0.03  # a narrowed place kept errs at most this
    narrow_rounds: int = 8  # Levenberg-Marquardt steps in f, tilt and roll
    min_sweep_deg: float = 20.0  # a rectified arc turning less than this about its centre is no circle's


@dataclass(frozen=True)
class CircleCorner:
    """A pitch circle (centre (centre_x_m, 0), radius_m) with a line ``x = x_m`` and a line ``y = y_m``; a rule per
    line: 1 the painted arc lies beyond it from the centre (a penalty arc's 16.5 m line), -1 on the centre's side, 0
    either (the whole circle painted, or the line through the centre)."""

    centre_x_m: float
    radius_m: float
    x_m: float
    y_m: float
    x_rule: int
    y_rule: int

    @property
    def shares(self) -> tuple[float, float]:
        """The two lines' distances from the centre, in radii (the ``x = c`` line first)."""
        return abs(self.x_m - self.centre_x_m) / self.radius_m, abs(self.y_m) / self.radius_m

    @property
    def handedness(self) -> int:
        """The sign of the cross product of the directions from the centre to the ``x = c`` line's foot and to the
        ``y = c`` line's (0 when either passes through the centre)."""
        return int(np.sign(self.x_m - self.centre_x_m) * np.sign(self.y_m))

    def kind(self) -> tuple:
        """What the rectified search tells apart: the shares, the rules and the handedness."""
        return (*(round(v, 6) for v in self.shares), self.x_rule, self.y_rule, self.handedness)


def circle_corners(pitch: PitchTemplate, circles: list[CircleChord], max_share: float) -> list[CircleCorner]:
    """Every pitch circle with every pair of straight ground markings, one of each direction, each of whose painted
    stretches passes within ``max_share`` radii of its centre. A circle whose chord is off its centre is a penalty
    arc, painted beyond that chord only (worked out once per pitch)."""
    return list(_circle_corners(pitch.dimensions, tuple(circles), max_share))


@functools.lru_cache(maxsize=8)
def _circle_corners(dimensions, circles: tuple[CircleChord, ...], max_share: float) -> tuple[CircleCorner, ...]:
    """:func:`circle_corners` of the pitch of these dimensions."""
    pitch = PitchTemplate(dimensions)
    out = []
    for circle in circles:
        c = np.array([circle.centre_x_m, 0.0])
        chord = circle.chord_x_m - circle.centre_x_m
        painted = None if abs(chord) < 1e-9 else c + np.array([math.copysign(circle.radius_m, chord), 0.0])
        near = {0: {}, 1: {}}  # axis (0: x = c lines, 1: y = c lines) -> offset -> rule
        for name, element in pitch.elements.items():
            if not pitch.is_on_ground(name) or not hasattr(element, "start_w"):
                continue
            a, b = np.asarray(element.start_w, float)[:2], np.asarray(element.end_w, float)[:2]
            axis = 0 if abs(a[0] - b[0]) < 1e-9 else (1 if abs(a[1] - b[1]) < 1e-9 else None)
            if axis is None:
                continue
            t = np.clip(np.dot(c - a, b - a) / max(np.dot(b - a, b - a), 1e-12), 0.0, 1.0)
            if np.linalg.norm(a + t * (b - a) - c) > max_share * circle.radius_m:
                continue
            offset = round(float(a[axis]), 4)
            rule = 0
            if painted is not None and abs(offset - c[axis]) > 1e-9:
                rule = 1 if (painted[axis] - offset) * (c[axis] - offset) < 0 else -1
            near[axis][offset] = rule
        out += [CircleCorner(circle.centre_x_m, circle.radius_m, x, y, x_rule, y_rule)
                for x, x_rule in near[0].items() for y, y_rule in near[1].items()]
    return tuple(out)


def arc_corner_homographies(arcs_px: list[np.ndarray], lines: list[ImageLine], frame_size,
                            corners: list[CircleCorner], focal_range_n: tuple[float, float], arc_band_px: float,
                            config: ArcCornerConfig = ArcCornerConfig()) -> np.ndarray:
    """(K, 3, 3) ground homographies (pitch (x, y, 1) metres -> normalised image points) putting a pitch circle on an
    arc's points and a corner's two lines on two straight markings (module docstring).

    Args:
        arcs_px: the arcs' points (:func:`~.court_arcs.arc_points`), frame pixels.
        lines: the straight markings (their two ends place each); the ``max_lines`` longest are paired, but for the
            arc's own straight pieces (within ``arc_band_px`` of it, per 1280 px of width).
        corners: the pitch's circles with their lines (:func:`circle_corners`).
        focal_range_n: (lo, hi) of f / s searched (s = W / 2).
    """
    if not arcs_px or len(lines) < 2 or not corners:
        return np.zeros((0, 3, 3))
    W, H = frame_size
    s, centre = W / 2.0, np.array([W / 2.0, H / 2.0])
    longest = sorted(range(len(lines)), key=lambda k: -lines[k].support_px)[:config.max_lines]
    of_corner = [corner.kind() for corner in corners]
    kinds = sorted(set(of_corner))
    members = [[corner for corner, kind in zip(corners, of_corner) if kind == each] for each in kinds]
    table_kinds = np.array(kinds, float)  # (C, 5): share x, share y, rule x, rule y, handedness
    focal = np.geomspace(*focal_range_n, config.focal_steps)
    tilt = np.radians(np.linspace(*config.tilt_range_deg, config.tilt_steps))
    grid = np.stack(np.meshgrid(focal, tilt, [0.0], indexing="ij"), axis=-1).reshape(-1, 3)
    out = []
    for arc_px in arcs_px:
        pieces = pieces_of(arc_px, lines, arc_band_px * W / 1280.0)
        usable = [k for k in longest if not pieces[k]]
        pairs = np.array([(a, b) for a in usable for b in usable if a != b], int).reshape(-1, 2)
        if not len(pairs):
            continue
        arc_n = (np.asarray(arc_px, float) - centre) / s
        ends_n = (np.array([[lines[a].ends_px(), lines[b].ends_px()] for a, b in pairs]) - centre) / s  # (P, 2, 2, 2)
        errors = _errors(grid, arc_n, ends_n, table_kinds, config.min_sweep_deg,
                         config.coarse_max_error)  # (G, P, C); over coarse_max_error: never narrowed
        floor = errors.min(axis=0)
        order = np.argsort(floor, axis=None)[:config.max_pairings]
        pair_k, kind_k = np.unravel_index(order, floor.shape)
        chosen = floor[pair_k, kind_k] <= config.coarse_max_error
        pair_k, kind_k = pair_k[chosen], kind_k[chosen]
        if not len(pair_k):
            continue
        start = grid[np.argmin(errors[:, pair_k, kind_k], axis=0)]
        place, error = _narrowed(start, arc_n, ends_n[pair_k], table_kinds[kind_k], focal_range_n, config)
        kept = error <= config.max_error
        if kept.any():
            out.append(_homographies(place[kept], arc_n, ends_n[pair_k[kept]],
                                     [members[k] for k in kind_k[kept]]))
    return np.concatenate(out) if out else np.zeros((0, 3, 3))


def _geometry(params: np.ndarray, arc_n: np.ndarray, ends_n: np.ndarray, min_sweep_deg: float):
    """The rectified arc and lines of places (G, 3), with line pairs' ends (P, 2, 2, 2) for every place or (G, 1, 2,
    2, 2) one each: the arc's points off their circle in radii (G, N), the circle's centre (G, 2), whether the arc
    counts (G,), the two lines' unit normals (G, P, 2, 2), their signed distances from the centre in radii (G, P, 2),
    the arc's side of each (G, P, 2: the sign of its mean point's offset against the centre's), whether the lines'
    ends are below the horizon (G, P). An arc turning less than ``min_sweep_deg`` about its centre does not count."""
    G, P = len(params), ends_n.shape[-4]
    off, c, r, arc_ok, turned, normal, distance, arc_side, below = rectified(
        params, arc_n, ends_n.reshape(*ends_n.shape[:-4], -1, 2, 2))
    arc_ok &= turned >= math.radians(min_sweep_deg)
    radius = np.where(np.isfinite(r), r, 1.0)
    return (np.where(np.isfinite(off), off, 0.0), c, arc_ok, normal.reshape(G, P, 2, 2),
            distance.reshape(G, P, 2) / radius[:, None, None], arc_side.reshape(G, P, 2), below.reshape(G, P, 2).all(
                axis=2))


def _residual_parts(params, arc_n, ends_n, kinds, min_sweep_deg: float):
    """(arc off (G, N), the lines' cosine (G, P), the distances off the kinds' (G, P, C, 2), where they count
    (G, P, C)); kinds (C, 5), or (G, 1, C, 5) one each."""
    off, _, arc_ok, normal, distance, arc_side, below = _geometry(params, arc_n, ends_n, min_sweep_deg)
    cosine = np.einsum("gpi,gpi->gp", normal[:, :, 0], normal[:, :, 1])
    off_share, kind_ok = _kind_parts(distance, arc_side, normal, kinds)
    return off, cosine, off_share, arc_ok[:, None, None] & below[:, :, None] & kind_ok


def _kind_parts(distance: np.ndarray, arc_side: np.ndarray, normal: np.ndarray, kinds: np.ndarray
                ) -> tuple[np.ndarray, np.ndarray]:
    """For line pairs' distances from the centre in radii (..., 2), the arc's side of each (..., 2) and their unit
    normals (..., 2, 2), with kinds (C, 5) (or broadcasting to (..., C, 5)): the distances off the kinds' (..., C, 2)
    and whether the pair lies about the centre as each kind asks (..., C)."""
    share, rule, hand = kinds[..., 0:2], kinds[..., 2:4], kinds[..., 4]
    off_share = np.abs(distance)[..., None, :] - share
    # 1: the arc beyond the line from the centre (its side against the centre's)
    beyond = np.sign(-np.sign(distance) * arc_side)[..., None, :]
    sided = ((rule == 0) | (beyond == rule)).all(axis=-1)
    foot = -np.sign(distance)[..., None] * normal  # (..., 2, 2): from the centre towards each line
    cross = np.sign(foot[..., 0, 0] * foot[..., 1, 1] - foot[..., 0, 1] * foot[..., 1, 0])[..., None]
    handed = (hand == 0) | (cross == hand)
    return off_share, sided & handed


def _errors(params, arc_n, ends_n, kinds, min_sweep_deg: float, within: float = math.inf) -> np.ndarray:
    """(G, P, C) the root mean square error of each place, line pair and kind (module docstring), inf where it does
    not count or where the arc's points and the lines' angle alone err over ``within`` (the kinds not asked there)."""
    off, _, arc_ok, normal, distance, arc_side, below = _geometry(params, arc_n, ends_n, min_sweep_deg)
    cosine = np.einsum("gpi,gpi->gp", normal[:, :, 0], normal[:, :, 1])
    base = np.mean(off**2, axis=1)[:, None] + cosine**2  # (G, P)
    g, p = np.nonzero(arc_ok[:, None] & below & (np.sqrt(base) <= within))
    off_share, kind_ok = _kind_parts(distance[g, p], arc_side[g, p], normal[g, p], kinds)
    errors = np.full((len(params), ends_n.shape[-4], len(kinds)), np.inf)
    errors[g, p] = np.where(kind_ok, np.sqrt(base[g, p][:, None] + (off_share**2).sum(axis=-1)), np.inf)
    return errors


def _narrowed(place: np.ndarray, arc_n: np.ndarray, ends_n: np.ndarray, kinds: np.ndarray,
              focal_range_n: tuple[float, float], config: ArcCornerConfig) -> tuple[np.ndarray, np.ndarray]:
    """Places (Q, 3), each with its own line pair's ends (Q, 2, 2, 2) and kind (Q, 5), narrowed by Levenberg-Marquardt
    steps in log f, tilt and roll (forward-difference Jacobians), every place at once: (Q, 3) places, (Q,) errors."""
    N = len(arc_n)
    ends_each, kinds_each = ends_n[:, None], kinds[:, None, None]

    def residuals(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # (Q, N + 3): their squares sum to the error's
        copies = len(x) // len(place)  # x: the places' parameters, stacked that many times
        off, cosine, off_share, ok = _residual_parts(np.column_stack([np.exp(x[:, 0]), x[:, 1:]]), arc_n,
                                                     np.tile(ends_each, (copies, 1, 1, 1, 1)),
                                                     np.tile(kinds_each, (copies, 1, 1, 1)), config.min_sweep_deg)
        return np.column_stack([off / math.sqrt(N), cosine[:, 0], off_share[:, 0, 0]]), ok[:, 0, 0]

    return narrowed(np.column_stack([np.log(place[:, 0]), place[:, 1:]]), residuals, [0, 1, 2], config.narrow_rounds,
                    focal_range_n)


def _homographies(places: np.ndarray, arc_n: np.ndarray, ends_n: np.ndarray, members: list[list[CircleCorner]]
                  ) -> np.ndarray:
    """(K, 3, 3) the homographies (pitch metres -> normalised image) of places (Q, 3), each with its line pair's ends
    (Q, 2, 2, 2) and the corners it stands for (each placed): ``H0 = (Rx(tilt) Rz(roll) K^-1)^-1`` times the inverse
    of the similarity taking the rectified plane onto the pitch (the circle's centre onto its centre, the foot of the
    ``x = c`` line, or of the other when that one passes through the centre, onto its side)."""
    rect = rectifiers(places)
    _, c, r, _, _, normal, distance, _, _ = rectified(places, arc_n, ends_n)  # normal (Q, 2, 2), distance (Q, 2)
    foot = -np.sign(distance)[..., None] * normal  # (Q, 2, 2)
    towards = np.arctan2(foot[..., 1], foot[..., 0])  # (Q, 2)
    placed = []
    for q, corners in enumerate(members):
        for corner in corners:
            if abs(corner.x_m - corner.centre_x_m) > 1e-9:
                turn = (0.0 if corner.x_m > corner.centre_x_m else math.pi) - towards[q, 0]
            else:
                turn = math.copysign(math.pi / 2, corner.y_m) - towards[q, 1]
            placed.append((q, turn, corner))
    if not placed:
        return np.zeros((0, 3, 3))
    which = np.array([q for q, _, _ in placed])
    alpha = np.array([turn for _, turn, _ in placed])
    scale = np.array([corner.radius_m for _, _, corner in placed]) / r[which]
    world_centre = np.array([(corner.centre_x_m, 0.0) for _, _, corner in placed])
    return placed_homographies(rect[which], c[which], alpha, scale, world_centre)
