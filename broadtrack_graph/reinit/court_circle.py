"""Court-model hypotheses from a pitch circle and the line across it: the centre circle with the halfway line (the
view a main camera shows most), a penalty arc with its 16.5 m line. No I/O.

A frame that shows the centre circle and the halfway line but not two straight markings of each
direction still fixes the ground homography. In normalised image coordinates (as in
:mod:`.court_lines`) let ``E`` be the circle's image conic and ``l`` the halfway line, which cuts
it at ``P1, P2`` (the images of (0, +-r)). The pole of ``l``, ``v = E^-1 l``, is where the tangents
at ``P1`` and ``P2`` meet: the vanishing point of the touchlines' direction. The image ``O`` of the
centre spot lies on the chord ``P1 P2``, at an unknown place; the line through ``O`` and ``v`` is
the image of the pitch's long axis and cuts the conic at ``Q1, Q2``, the images of (+-r, 0). Since
``O . l = 0`` and ``v = E^-1 l``, the cuts solve ``a^2 O^T E O + b^2 v^T E v = 0`` for
``a O + b v``. Four points ``P1, P2, Q1, Q2`` give H by the direct linear transform; ``O`` is tried
along the chord (and each labelling of the four points): a camera's homography has ``K^-1 h1`` and
``K^-1 h2`` orthogonal and of equal norm for the principal point at the image centre
(:func:`~.court_lines.focal_and_mismatch`), so the places where that mismatch has a local minimum
are kept, narrowed by golden-section search, then decomposed and gated like the straight
markings' (:func:`~.court_lines.cameras_from_homographies`) and scored on the map with them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.detect.marking_ellipses import ImageEllipse
from broadtrack_graph.geometry.matrices import cross3, inverses
from broadtrack_graph.reinit.court_lines import focal_and_mismatch


@dataclass(frozen=True)
class CourtCircleConfig:
    """Settings of :func:`circle_line_homographies`."""

    centre_steps: int = 64  # places of the centre spot's image tried along the chord (its ends excluded) ...
    refine_iterations: int = 16  # ... each local minimum of the axes' mismatch narrowed by golden-section steps
    chord_offset_slack: float = 0.35  # a line's offset from the ellipse's centre (a share of its half width across
    #                                   the line) within this of the chord's offset from the circle's (0 for a diameter)


def ellipse_conic_n(ellipse: ImageEllipse, frame_size) -> np.ndarray:
    """(3, 3) the ellipse as a conic ``x^T E x = 0`` in normalised coordinates (x_n = (u - W / 2) / (W / 2), ...)."""
    W, H = frame_size
    s = W / 2.0
    cx, cy = (np.asarray(ellipse.centre_px, float) - [W / 2.0, H / 2.0]) / s
    a, b = (v / s for v in ellipse.semi_axes_px)
    c, d = math.cos(ellipse.angle_rad), math.sin(ellipse.angle_rad)
    rotation = np.array([[c, d], [-d, c]])  # frame -> ellipse axes
    M = rotation.T @ np.diag([1.0 / a**2, 1.0 / b**2]) @ rotation
    centre = np.array([cx, cy])
    conic = np.zeros((3, 3))
    conic[:2, :2] = M
    conic[:2, 2] = conic[2, :2] = -M @ centre
    conic[2, 2] = centre @ M @ centre - 1.0
    return conic


def _homographies_from_points(image_h: np.ndarray, world_xy: np.ndarray) -> np.ndarray:
    """(K, 3, 3) H with ``H (x, y, 1) ~ image point`` from four correspondences each: image_h (K, 4, 3)
    homogeneous, world_xy (K, 4, 2) metres; every K at once, unit Frobenius norm (NaN where three of the four
    points of either side are on one line).

    Through the projective basis: B = [l1 p1, l2 p2, l3 p3] with [p1 p2 p3] l = p4 maps e1, e2, e3 and (1, 1, 1)
    to the four points, so ``H = B_image B_world^-1``: two 3x3 solves a homography instead of an 8x9 SVD.
    """
    K = len(image_h)
    world_h = np.concatenate([world_xy, np.ones((K, 4, 1))], axis=2)  # (K, 4, 3)
    with np.errstate(invalid="ignore", divide="ignore"):
        B_image, B_world = _projective_basis(np.asarray(image_h, float)), _projective_basis(world_h)
        H = B_image @ inverses(B_world)
        return H / np.linalg.norm(H, axis=(1, 2), keepdims=True)


def _projective_basis(points_h: np.ndarray) -> np.ndarray:
    """(K, 3, 3) the matrices mapping e1, e2, e3 and (1, 1, 1) to the four points (K, 4, 3) (NaN where degenerate)."""
    first3 = np.swapaxes(points_h[:, :3], 1, 2)  # (K, 3, 3): the points as columns
    weights = inverses(first3) @ points_h[:, 3, :, None]  # (K, 3, 1)
    return first3 * np.swapaxes(weights, 1, 2)


@dataclass(frozen=True)
class CircleChord:
    """A pitch circle with a straight marking across it: centre (centre_x_m, 0), radius_m, the line x = chord_x_m."""

    name: str
    centre_x_m: float
    radius_m: float
    chord_x_m: float

    def world_points(self) -> np.ndarray:
        """(4, 2) the line's two cuts (y > 0 first) and the long axis's two cuts (x larger first), metres."""
        d = self.chord_x_m - self.centre_x_m
        h = math.sqrt(self.radius_m**2 - d**2)
        return np.array([[self.chord_x_m, h], [self.chord_x_m, -h], [self.centre_x_m + self.radius_m, 0.0],
                         [self.centre_x_m - self.radius_m, 0.0]])


def pitch_circle_chords(pitch) -> list[CircleChord]:
    """The centre circle with the halfway line, and each penalty arc's circle with its penalty area's 16.5 m line."""
    d = pitch.dimensions
    half_l, r = d.length_m / 2, d.centre_circle_radius_m
    mark_x, box_x = half_l - d.penalty_mark_distance_m, half_l - d.penalty_area_depth_m
    return [CircleChord("centre circle", 0.0, r, 0.0), CircleChord("right penalty arc", mark_x, r, box_x),
            CircleChord("left penalty arc", -mark_x, r, -box_x)]


def circle_line_homographies(ellipses: list[ImageEllipse], lines_n: np.ndarray, frame_size,
                             circles: list[CircleChord], config: CourtCircleConfig = CourtCircleConfig()) -> np.ndarray:
    """(K, 3, 3) ground homographies (normalised image coordinates) putting a pitch circle on an ellipse and its
    chord's line on an image line (L, 3) that cuts it, for every ellipse, circle and line at once.

    The module docstring's construction with the chord anywhere: the pole of the chord's line is the image of
    the pole of ``x = c`` (on the long axis, at infinity for a diameter), and the image M of (c, 0), tried
    along the chord, with the pole gives the long axis, which cuts the conic at the images of (cx +- r, 0). A
    line is taken as a circle's chord only where it cuts the ellipse about as far from its centre as the chord
    cuts the circle (``chord_offset_slack``).
    """
    chords = []  # (E, P1, P2, pole, world points (4, 2), the world's reflections to add)
    lines_n = np.asarray(lines_n, float).reshape(-1, 3)
    for ellipse in ellipses:
        E = ellipse_conic_n(ellipse, frame_size)
        E_inv = np.linalg.inv(E)
        # How far each line is from the ellipse's centre, as a share of the ellipse's half width across the line.
        centre = E_inv[:, 2] / E_inv[2, 2]
        spread = np.sqrt(np.maximum(-np.einsum("li,ij,lj->l", lines_n[:, :2], E_inv[:2, :2] - np.outer(
            centre[:2], centre[:2]) * E_inv[2, 2], lines_n[:, :2]) / E_inv[2, 2], 1e-18))
        offset = np.abs(lines_n @ centre) / spread
        for circle in circles:
            share = abs(circle.chord_x_m - circle.centre_x_m) / circle.radius_m
            diameter = share < 1e-9
            world = circle.world_points()
            # The other order of P1, P2 is the world's reflection y -> -y (the axes' mismatch is the same, so the
            # places are searched once; mirror images are gated later); the other order of Q1, Q2 is searched on
            # its own, but for a diameter, where it is the reflection x -> -x.
            reflections = [np.diag([sx, sy, 1.0]) for sx in ((1.0, -1.0) if diameter else (1.0,)) for sy in (1.0, -1.0)]
            for k in np.nonzero(np.abs(offset - share) <= config.chord_offset_slack)[0]:
                cuts = _line_cuts(E, lines_n[k])
                if cuts is None:
                    continue
                for points in ([world] if diameter else [world, world[[0, 1, 3, 2]]]):
                    chords.append((E, cuts[0], cuts[1], E_inv @ lines_n[k], points, reflections))
    if not chords:
        return np.zeros((0, 3, 3))
    found, owner = _Chords(chords).best_homographies(config.centre_steps, config.refine_iterations)
    out = [found[owner == c] @ reflection for c, chord in enumerate(chords) for reflection in chord[5]]
    return np.concatenate(out)


class _OneParameterSearch:
    """Homographies that depend on one parameter per item, each item searched over the same range: a grid, then the
    local minima of the axes' mismatch narrowed by golden-section search (on a detected ellipse the minimum can be
    shallow or off the right place: every grid homography is kept as well, and the map decides among all)."""

    count: int
    span: tuple[float, float] = (0.0, 1.0)  # the parameter's range (its ends excluded)

    def homographies(self, which: np.ndarray, params: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(N, 3, 3) H and (N,) the axes' mismatch (inf where undefined) of items ``which`` at ``params`` (N,)."""
        raise NotImplementedError

    def best_homographies(self, steps: int, iterations: int) -> tuple[np.ndarray, np.ndarray]:
        """The grid's homographies and the narrowed minima's, with the item of each."""
        lo_span, hi_span = self.span
        grid = np.linspace(lo_span, hi_span, steps + 2)[1:-1]
        which = np.repeat(np.arange(self.count), steps)
        H, mismatch = self.homographies(which, np.tile(grid, self.count))
        table = mismatch.reshape(self.count, steps)
        inner = np.arange(1, steps - 1)
        is_min = ((table[:, inner] <= table[:, inner - 1]) & (table[:, inner] <= table[:, inner + 1])
                  & np.isfinite(table[:, inner]))
        item, cell = np.nonzero(is_min)
        lo, hi = grid[inner[cell] - 1], grid[inner[cell] + 1]
        ratio = (math.sqrt(5.0) - 1.0) / 2.0
        for _ in range(iterations if len(item) else 0):
            a, b = hi - ratio * (hi - lo), lo + ratio * (hi - lo)
            _, fa = self.homographies(np.concatenate([item, item]), np.concatenate([a, b]))
            left = fa[:len(item)] <= fa[len(item):]
            hi, lo = np.where(left, b, hi), np.where(left, lo, a)
        narrowed, _ = self.homographies(item, 0.5 * (lo + hi))
        keep = np.isfinite(mismatch)
        return np.concatenate([H[keep], narrowed]), np.concatenate([which[keep], item])


class _Chords(_OneParameterSearch):
    """Chords P1 P2 of circles' image conics E, each with the pole of its line and its four world points: the
    homography for each place of the image M of the chord's middle on it, every chord at once."""

    def __init__(self, chords: list) -> None:
        self.E = np.stack([c[0] for c in chords])
        self.p1, self.p2 = np.stack([c[1] for c in chords]), np.stack([c[2] for c in chords])
        self.pole = np.stack([c[3] for c in chords])
        self.world = np.stack([c[4] for c in chords])
        self.vEv = np.einsum("ci,cij,cj->c", self.pole, self.E, self.pole)
        self.count = len(self.E)

    def homographies(self, which: np.ndarray, places: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(N, 3, 3) H and (N,) the axes' mismatch (inf where the long axis misses the conic) for chord ``which``
        (N,) with M at ``places`` (N,) along it (0: P1, 1: P2)."""
        p1, p2, pole, E = self.p1[which], self.p2[which], self.pole[which], self.E[which]
        M = p1 + places[:, None] * (p2 - p1)
        ratio = -np.einsum("ni,nij,nj->n", M, E, M) / self.vEv[which]
        valid = ratio > 0
        t = np.sqrt(np.where(valid, ratio, 0.0))[:, None]
        image = np.stack([p1, p2, M + t * pole, M - t * pole], axis=1)
        H = _homographies_from_points(image, self.world[which])
        _, mismatch = focal_and_mismatch(H)
        return H, np.where(valid, mismatch, np.inf)


def circle_pole_homographies(ellipses: list[ImageEllipse], lines_n: np.ndarray, frame_size, radius_m: float,
                             offset_m: float, config: CourtCircleConfig = CourtCircleConfig()) -> np.ndarray:
    """(K, 3, 3) ground homographies (normalised image coordinates) putting the centre circle (radius_m about the
    centre spot) on an ellipse and the line y = +-offset_m (a touchline) on an image line (L, 3) that misses it.

    The pole of the touchline's image is the image of (0, r^2 / c), on the halfway line; the halfway line's image is
    a line d through it at an unknown angle, tried over half a turn. d cuts the ellipse at the images of (0, -+r)
    and the touchline at the image of (0, c); the cross ratio of these with (0, 0) places the centre spot's image O
    on d; the pole of d is the long axis's vanishing point, and the line through O and it cuts the ellipse at the
    images of (+-r, 0). The two orders of the cuts on d are searched; the world's reflections add the rest.
    """
    r, c = radius_m, offset_m
    worlds = [np.array([[0.0, -r], [0.0, r], [r, 0.0], [-r, 0.0]]), np.array([[0.0, r], [0.0, -r], [r, 0.0], [-r, 0.0]])]
    items = []  # (E, the touchline's image, world points, the y-values of the cuts)
    for ellipse in ellipses:
        E = ellipse_conic_n(ellipse, frame_size)
        for line in np.asarray(lines_n, float).reshape(-1, 3):
            if _line_cuts(E, line) is not None:
                continue  # a touchline does not cross the centre circle
            for world in worlds:
                items.append((E, line, world))
    if not items:
        return np.zeros((0, 3, 3))
    found, owner = _Pencils(items, c).best_homographies(config.centre_steps, config.refine_iterations)
    reflections = [np.diag([sx, sy, 1.0]) for sx in (1.0, -1.0) for sy in (1.0, -1.0)]
    return np.concatenate([found @ reflection for reflection in reflections])


class _Pencils(_OneParameterSearch):
    """Lines d through the pole of a touchline's image, one angle each: the homography of each (module docstring of
    :func:`circle_pole_homographies`)."""

    span = (0.0, math.pi)

    def __init__(self, items: list, offset_m: float) -> None:
        self.E = np.stack([item[0] for item in items])
        self.line = np.stack([item[1] for item in items])
        self.world = np.stack([item[2] for item in items])
        self.E_inv = np.linalg.inv(self.E)
        self.pole = np.einsum("nij,nj->ni", self.E_inv, self.line)
        self.offset_m, self.count = offset_m, len(items)

    def homographies(self, which: np.ndarray, angles: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        E, E_inv, line, pole, world = self.E[which], self.E_inv[which], self.line[which], self.pole[which], self.world[which]
        direction = np.column_stack([np.cos(angles), np.sin(angles), np.zeros(len(angles))])
        d = cross3(pole, direction)
        d1, d2, cut = _line_cuts_many(E, d)
        crossing = cross3(d, line)
        # The crossing's place t along D1 -> D2 (the component along the chord), then O's by the cross ratio of the
        # world's (-r or r, r or -r, c, 0) in the cuts' order.
        chord = (d2 - d1)[:, :2]
        ahead = np.abs(crossing[:, 2]) > 1e-12
        x = np.where(ahead[:, None], crossing[:, :2] / np.where(ahead, crossing[:, 2], 1.0)[:, None], 0.0)
        t3 = np.einsum("ni,ni->n", x - d1[:, :2], chord) / np.maximum(np.einsum("ni,ni->n", chord, chord), 1e-18)
        y1, y2 = world[:, 0, 1], world[:, 1, 1]
        c = self.offset_m
        ratio_w = ((c - y1) * (0.0 - y2)) / ((c - y2) * (0.0 - y1))
        with np.errstate(divide="ignore", invalid="ignore"):
            t4 = t3 / (t3 - ratio_w * (t3 - 1.0))
        O = d1 + t4[:, None] * (d2 - d1)
        v = np.einsum("nij,nj->ni", E_inv, d)
        ratio = -np.einsum("ni,nij,nj->n", O, E, O) / np.einsum("ni,nij,nj->n", v, E, v)
        valid = cut & ahead & np.isfinite(t4) & (ratio > 0)
        s = np.sqrt(np.where(valid, ratio, 0.0))[:, None]
        image = np.stack([d1, d2, O + s * v, O - s * v], axis=1)
        image = np.where(valid[:, None, None], image, np.array([[1.0, 0, 1], [0, 1.0, 1], [-1.0, 0, 1], [0, -1.0, 1]]))
        H = _homographies_from_points(image, world)
        _, mismatch = focal_and_mismatch(H)
        return H, np.where(valid, mismatch, np.inf)


def _line_cuts_many(E: np.ndarray, lines: np.ndarray):
    """The two points (homogeneous, w = 1) where each line (N, 3) cuts its conic E (N, 3, 3), and whether it does."""
    normal = lines[:, :2]
    norm2 = np.maximum(np.einsum("ni,ni->n", normal, normal), 1e-24)
    foot = -lines[:, 2:3] * normal / norm2[:, None]
    direction = np.column_stack([-normal[:, 1], normal[:, 0]]) / np.sqrt(norm2)[:, None]
    p0 = np.column_stack([foot, np.ones(len(lines))])
    d = np.column_stack([direction, np.zeros(len(lines))])
    A = np.einsum("ni,nij,nj->n", d, E, d)
    B = 2.0 * np.einsum("ni,nij,nj->n", p0, E, d)
    C = np.einsum("ni,nij,nj->n", p0, E, p0)
    disc = B * B - 4.0 * A * C
    cut = (disc > 0) & (np.abs(A) > 1e-15)
    root = np.sqrt(np.where(cut, disc, 0.0))
    A = np.where(cut, A, 1.0)
    return p0 + ((-B + root) / (2 * A))[:, None] * d, p0 + ((-B - root) / (2 * A))[:, None] * d, cut


def _line_cuts(E: np.ndarray, line: np.ndarray):
    """The two points (homogeneous, w = 1) where a line (3,) cuts the conic E, or None (:func:`_line_cuts_many`)."""
    first, second, cut = _line_cuts_many(E[None], np.asarray(line, float)[None])
    return (first[0], second[0]) if cut[0] else None