"""Court-model hypotheses from the centre circle and the halfway line: the view a main camera shows most. No I/O.

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

from broadtrack_graph.detect.marking_structures import ImageEllipse
from broadtrack_graph.reinit.court_lines import focal_and_mismatch


@dataclass(frozen=True)
class CourtCircleConfig:
    """Settings of :func:`circle_line_homographies`."""

    centre_steps: int = 64  # places of the centre spot's image tried along the chord (its ends excluded) ...
    refine_iterations: int = 16  # ... each local minimum of the axes' mismatch narrowed by golden-section steps
    max_line_offset: float = 0.6  # the halfway line passes within this share of the minor semi-axis of the
    #                               ellipse's centre (the image of the circle's centre is near it)


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
    homogeneous, world_xy (4, 2) metres; the direct linear transform, every K at once."""
    K = len(image_h)
    X = np.column_stack([world_xy, np.ones(4)])  # (4, 3)
    rows = np.zeros((K, 8, 9))
    u, v, w = image_h[..., 0], image_h[..., 1], image_h[..., 2]
    for k in range(4):
        rows[:, 2 * k, 3:6] = -w[:, k, None] * X[k]
        rows[:, 2 * k, 6:9] = v[:, k, None] * X[k]
        rows[:, 2 * k + 1, 0:3] = w[:, k, None] * X[k]
        rows[:, 2 * k + 1, 6:9] = -u[:, k, None] * X[k]
    _, _, vt = np.linalg.svd(rows)
    return vt[:, -1].reshape(K, 3, 3)


def circle_line_homographies(ellipse: ImageEllipse, lines_n: np.ndarray, frame_size, radius_m: float,
                             config: CourtCircleConfig = CourtCircleConfig()) -> np.ndarray:
    """(K, 3, 3) ground homographies (normalised image coordinates) putting the centre circle (radius_m, about the
    centre spot) on the ellipse and the halfway line on each image line (L, 3) that cuts it near its centre."""
    W = frame_size[0]
    E = ellipse_conic_n(ellipse, frame_size)
    s = W / 2.0
    centre_n = (np.asarray(ellipse.centre_px, float) - [W / 2.0, frame_size[1] / 2.0]) / s
    minor_n = ellipse.semi_axes_px[1] / s
    out = []
    steps = np.linspace(0.0, 1.0, config.centre_steps + 2)[1:-1]
    r = radius_m
    world = np.array([[0.0, r], [0.0, -r], [r, 0.0], [-r, 0.0]])  # P1, P2, Q1, Q2
    # The other labellings of the four points are the world's reflections about the axes (the mirror images are
    # gated later); the axes' mismatch is the same for all four, so the places are searched once.
    reflections = [np.diag([sx, sy, 1.0]) for sx in (1.0, -1.0) for sy in (1.0, -1.0)]
    E_inv = np.linalg.inv(E)
    for line in np.asarray(lines_n, float).reshape(-1, 3):
        if abs(line[:2] @ centre_n + line[2]) > config.max_line_offset * minor_n:
            continue
        cuts = _line_cuts(E, line)
        if cuts is None:
            continue
        found = _Chord(E, cuts[0], cuts[1], E_inv @ line).best_homographies(world, steps, config.refine_iterations)
        out += [found @ reflection for reflection in reflections]
    return np.concatenate(out) if out else np.zeros((0, 3, 3))


class _Chord:
    """The halfway line's chord P1 P2 of the circle's image conic E, with the pole of the line (the vanishing
    point of the touchlines' direction): the homography for each place of the centre spot's image on it."""

    def __init__(self, E: np.ndarray, p1: np.ndarray, p2: np.ndarray, pole: np.ndarray) -> None:
        self.E, self.p1, self.p2, self.pole = E, p1, p2, pole
        self.vEv = pole @ E @ pole

    def homographies(self, places: np.ndarray, world: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(S, 3, 3) H and (S,) the axes' mismatch (inf where the long axis misses the conic) for the centre
        spot's image at the places (S,) along the chord (0: P1, 1: P2)."""
        O = self.p1[None, :] + places[:, None] * (self.p2 - self.p1)[None, :]
        ratio = -np.einsum("si,ij,sj->s", O, self.E, O) / self.vEv
        valid = ratio > 0
        t = np.sqrt(np.where(valid, ratio, 0.0))[:, None]
        q1, q2 = O + t * self.pole[None, :], O - t * self.pole[None, :]
        image = np.stack([np.broadcast_to(self.p1, q1.shape), np.broadcast_to(self.p2, q1.shape), q1, q2], axis=1)
        H = _homographies_from_points(image, world)
        _, mismatch = focal_and_mismatch(H)
        return H, np.where(valid, mismatch, np.inf)

    def best_homographies(self, world: np.ndarray, steps: np.ndarray, iterations: int) -> np.ndarray:
        """The homographies on the grid ``steps`` of places along the chord, and at the places where the axes'
        mismatch has a local minimum, narrowed by golden-section search in the grid cells either side (on a
        detected ellipse the minimum can also be shallow or off the right place: the map decides among all)."""
        grid, mismatch = self.homographies(steps, world)
        grid = grid[np.isfinite(mismatch)]
        inner = np.arange(1, len(steps) - 1)
        minima = inner[(mismatch[inner] <= mismatch[inner - 1]) & (mismatch[inner] <= mismatch[inner + 1])
                       & np.isfinite(mismatch[inner])]
        if not len(minima):
            return grid
        lo, hi = steps[minima - 1], steps[minima + 1]
        ratio = (math.sqrt(5.0) - 1.0) / 2.0
        for _ in range(iterations):
            a, b = hi - ratio * (hi - lo), lo + ratio * (hi - lo)
            _, fa = self.homographies(a, world)
            _, fb = self.homographies(b, world)
            left = fa <= fb
            hi, lo = np.where(left, b, hi), np.where(left, lo, a)
        return np.concatenate([grid, self.homographies(0.5 * (lo + hi), world)[0]])




def _line_cuts(E: np.ndarray, line: np.ndarray):
    """The two points (homogeneous, w = 1) where a line (3,) cuts the conic E, or None."""
    normal = line[:2]
    norm = np.linalg.norm(normal)
    if norm < 1e-12:
        return None
    foot = -line[2] * normal / norm**2  # the line's point nearest the origin
    direction = np.array([-normal[1], normal[0]]) / norm
    p0, d = np.append(foot, 1.0), np.append(direction, 0.0)
    A, B, C = d @ E @ d, 2.0 * (p0 @ E @ d), p0 @ E @ p0
    disc = B * B - 4.0 * A * C
    if abs(A) < 1e-15 or disc <= 0:
        return None
    root = math.sqrt(disc)
    return p0 + (-B + root) / (2 * A) * d, p0 + (-B - root) / (2 * A) * d
