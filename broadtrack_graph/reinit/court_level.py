"""Court-model hypotheses from two lines of one direction and one line across them, the camera level. No I/O.

A smeared frame keeps the markings along its smear and loses those across it; a narrow or a low view can show
two lines of one direction and a single one of the other (a 16.5 m line, a touchline and the penalty area's side),
the rest of its markings an arc the map gives only in pieces. Four lines fix the ground homography
(:mod:`.court_lines`), three and one too (:mod:`.court_pencil`); two and one fix a camera whose roll is known. A
broadcast camera stands on a levelled tripod head (its roll within a degree or two), and a level camera (roll 0)
draws the horizon across the image: every point of it at one height.

* the two lines meet at their direction's vanishing point ``v_A``, on the horizon; the horizon is the image's
  horizontal line through it, ``h = v_A x (1, 0, 0)``;
* the line across meets the horizon at the other direction's vanishing point ``v_B = h x l``, and the two points'
  orthogonality gives the focal length, ``f^2 = -(v_A . v_B)`` about the image centre (:mod:`.court_lines`);
* with ``v_A`` and ``v_B`` known, the two lines put on two pitch lines fix their family's map ``c = a tau + b`` in
  the pencil coordinate of :mod:`.court_lines`, a camera's equal axes (``|K^-1 h1| = |K^-1 h2|``) give the other
  family's ``|a|`` and the line across its ``b``, and H is :mod:`.court_lines`' closed form.

A camera rolled by a degree or two is found a little off and the fit that follows, its roll free, moves it onto the
markings. The vanishing point of two lines horizontal and parallel in the image (a camera square to them) is the
horizon's own direction: the horizon is not fixed, and such a pair gives no hypothesis (a view square to the
touchlines shows the lines across it too). Every assignment (the two lines on two pitch lines of one direction in
either order, the line across on any pitch line of the other, both signs) is formed at once, gated by
:func:`~.court_lines.cameras_from_homographies`. Two lines and one fix a camera exactly: the court model tries them
as a tier of last resort and takes their camera only with more of the markings explained and at
``exact_fit_confidence`` (:mod:`.court_tiers`).
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.detect.marking_structures import ImageLine
from broadtrack_graph.geometry.matrices import cross3
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.court_across import family_and_across_hypotheses
from broadtrack_graph.reinit.court_families import CourtLineConfig
from broadtrack_graph.reinit.court_lines import (
    PlaneHypotheses,
    homographies_from_maps,
    pair_maps,
)


@dataclass(frozen=True)
class CourtLevelConfig:
    """Settings of :func:`level_hypotheses`."""

    families: int = 2  # the best distinct vanishing points of two lines or more taken as the family of two
    max_family_lines: int = 3  # the family's best supported lines, taken two at a time
    max_across_lines: int = 8  # the best supported other lines tried as the line across
    # a pair whose meeting point is this near the horizon's own direction, (1, 0, 0) (the unit homogeneous point's
    # y and w both under it), fixes no horizon
    min_horizon_lever: float = 1e-6


def level_hypotheses(lines: list[ImageLine], frame_size: tuple[int, int], pitch: PitchTemplate,
                     config: CourtLevelConfig = CourtLevelConfig(),
                     line_config: CourtLineConfig = CourtLineConfig(), hidden_px: np.ndarray | None = None
                     ) -> PlaneHypotheses:
    """Every level camera putting two lines of an image family on two pitch lines of one direction and another
    image line on a pitch line of the other direction (module docstring), gated by
    :func:`~.court_lines.cameras_from_homographies`.

    Args:
        lines: the straight markings of the map (frame pixels).
        frame_size: (W, H) pixels.
        hidden_px: (L,) each line's length the players hide (:func:`~.court_families.vanishing_votes`).
    """
    return family_and_across_hypotheses(
        lines, frame_size, pitch, 2, config.families, config.max_family_lines, config.max_across_lines,
        functools.partial(level_homographies, min_horizon_lever=config.min_horizon_lever), line_config, hidden_px)


def level_homographies(pair_n: np.ndarray, across_n: np.ndarray, pair_offsets_m: np.ndarray,
                       across_offsets_m: np.ndarray, a_is_x: bool, min_horizon_lever: float = 1e-6) -> np.ndarray:
    """(K, 3, 3) the homographies (pitch metres -> normalised image points) of a level camera putting two image lines
    of one direction (2, 3) on two pitch lines of ``pair_offsets_m`` (either order) and each line across (n, 3) on
    each pitch line of ``across_offsets_m``, both signs of the across family's map (module docstring); ``a_is_x``:
    the pair is the y = c direction. Lines in normalised coordinates; none when the pair fixes no horizon."""
    q = np.array([0.0, 0.0, 1.0])
    v_a = cross3(pair_n[0], pair_n[1])
    v_a = v_a / max(float(np.linalg.norm(v_a)), 1e-12)
    if max(abs(v_a[1]), abs(v_a[2])) < min_horizon_lever:
        return np.zeros((0, 3, 3))
    horizon = cross3(v_a, np.array([1.0, 0.0, 0.0]))  # the image's horizontal line through v_a
    v_b = cross3(horizon[None, :], across_n)  # (n, 3): where each line across meets the horizon
    v_b = v_b / np.maximum(np.linalg.norm(v_b, axis=1, keepdims=True), 1e-12)
    with np.errstate(invalid="ignore", divide="ignore"):
        f2 = -(v_b[:, :2] @ v_a[:2]) / (v_b[:, 2] * v_a[2])  # (n,)
        # The pair's map c = a tau + b in the pencil coordinate tau = (l . q) / (l . v_b), fixed by its two lines;
        # the line across's coordinate in the pencil through v_b, against v_a.
        tau_pair = (pair_n @ q)[None, :] / (v_b @ pair_n.T)  # (n, 2)
        tau_across = (across_n @ q) / (across_n @ v_a)  # (n,)
    a_pair, b_pair = pair_maps(tau_pair, pair_offsets_m)  # (n, M): every ordered pair of pitch lines
    with np.errstate(invalid="ignore", divide="ignore"):
        norm_a = np.sqrt((v_a[0] ** 2 + v_a[1] ** 2) / f2 + v_a[2] ** 2)  # |K^-1 v_a|
        norm_b = np.sqrt((v_b[:, 0] ** 2 + v_b[:, 1] ** 2) / f2 + v_b[:, 2] ** 2)
        # Equal norms of K^-1 h1 = -K^-1 v_x / a_y and K^-1 h2 = -K^-1 v_y / a_x: |a_across| |v_b| = |a_pair| |v_a|.
        a_mag = np.abs(a_pair) * (norm_a / norm_b)[:, None]  # (n, M)
    ok = (f2 > 0)[:, None] & np.isfinite(a_mag) & np.isfinite(b_pair) & np.isfinite(tau_across)[:, None]
    across, map_of = np.nonzero(ok)
    if not len(across):
        return np.zeros((0, 3, 3))
    K, C, S = np.meshgrid(np.arange(len(across)), np.arange(len(across_offsets_m)), (-1.0, 1.0), indexing="ij")
    K, C, S = K.ravel(), C.ravel(), S.ravel()
    n, m = across[K], map_of[K]
    a_across = S * a_mag[n, m]
    b_across = across_offsets_m[C] - a_across * tau_across[n]
    pair, other = (np.broadcast_to(v_a, (len(n), 3)), a_pair[n, m], b_pair[n, m]), (v_b[n], a_across, b_across)
    (v_x, a_x, b_x), (v_y, a_y, b_y) = (pair, other) if a_is_x else (other, pair)  # a_is_x: v_x = v_a
    H = homographies_from_maps(v_x, v_y, a_x, b_x, a_y, b_y)
    return H[np.all(np.isfinite(H), axis=(1, 2))]
