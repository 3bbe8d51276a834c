"""Court-model hypotheses from three lines of one direction and one line across them. No I/O.

A zoomed view of a goal mouth shows three markings of one direction (the goal line, the goal area's
front, the 16.5 m line) and often a single one across them (a goal area's side). Four lines of two
directions, two each, fix the ground homography (:mod:`.court_lines`); three and one do too:

* the three lines meet at their direction's vanishing point ``v_A``; along the pencil of lines through
  it, their pitch offsets ``c`` and a projective coordinate ``tau`` of the line are related by a 1D
  homography, ``tau = (alpha c + beta) / (gamma c + 1)``, which three lines fix;
* the line of the pencil at ``c = infinity`` is the horizon, ``h = v_A x (gamma q - alpha u)`` (``tau =
  (l . q) / (l . u)``, ``q`` the image centre, ``u`` the point at infinity across the lines);
* the line across meets the horizon at the other direction's vanishing point ``v_B = h x l``; with ``v_A``
  and ``v_B`` known, the family's offsets are affine in the pencil coordinate of :mod:`.court_lines`
  (``c = a tau' + b``, least squares over its three lines), a camera's equal axes (``|K^-1 h1| = |K^-1 h2|``)
  give the other family's ``|a|`` and the line across its ``b``, and H is :mod:`.court_lines`' closed form.

Nothing is assumed of the camera's roll. A view with little perspective (a long lens far off) fixes the
horizon poorly; the map scores and the fit that follows decide. Every assignment (three lines of a family,
in their order across the image, on three pitch lines in either order; one other line on any pitch line of
the other direction; both signs) is formed at once, gated by :func:`~.court_lines.cameras_from_homographies`.
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.detect.marking_structures import ImageLine
from broadtrack_graph.geometry.matrices import cross3
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.court_across import family_and_across_hypotheses
from broadtrack_graph.reinit.court_families import CourtLineConfig
from broadtrack_graph.reinit.court_lines import PlaneHypotheses, homographies_from_maps


@dataclass(frozen=True)
class CourtPencilConfig:
    """Settings of :func:`pencil_hypotheses`."""

    families: int = 2  # the best distinct vanishing points taken as the family of three or more lines
    max_family_lines: int = 4  # the family's best supported lines, taken three at a time
    max_across_lines: int = 8  # the best supported other lines tried as the line across (arc pieces found as short
    #                            lines can outnumber a goal area's side)


def pencil_hypotheses(lines: list[ImageLine], frame_size: tuple[int, int], pitch: PitchTemplate,
                      config: CourtPencilConfig = CourtPencilConfig(),
                      line_config: CourtLineConfig = CourtLineConfig(), hidden_px: np.ndarray | None = None
                      ) -> PlaneHypotheses:
    """Every camera putting three lines of an image family on three pitch lines of one direction and another image
    line on a pitch line of the other direction (module docstring), gated by
    :func:`~.court_lines.cameras_from_homographies`.

    Args:
        lines: the straight markings of the map (frame pixels).
        frame_size: (W, H) pixels.
        hidden_px: (L,) each line's length the players hide (:func:`~.court_families.vanishing_votes`).
    """
    # Only a meeting point of three lines or more can be the family's: a pair's (the commonest, a long line's with
    # any other) would take a place of the few tried.
    return family_and_across_hypotheses(lines, frame_size, pitch, 3, config.families, config.max_family_lines,
                                        config.max_across_lines, _homographies, line_config, hidden_px)


def _homographies(family_n: np.ndarray, across_n: np.ndarray, family_offsets_m: np.ndarray,
                  across_offsets_m: np.ndarray, a_is_x: bool) -> np.ndarray:
    """(K, 3, 3) the homographies of three family lines (3, 3) and the lines across (n, 3) (normalised coordinates),
    for every assignment of the family's lines to three pitch offsets and of one line across to one offset of the
    other direction; ``a_is_x``: the family is the y = c direction."""
    q = np.array([0.0, 0.0, 1.0])
    v_a = np.linalg.svd(family_n)[2][-1]  # the three lines' meeting point
    normal = family_n[:, :2] * np.sign(family_n[:, :2] @ family_n[0, :2])[:, None]
    u = np.array([*normal.mean(axis=0), 0.0])  # the point at infinity across the lines: l . u never 0
    tau = (family_n @ q) / (family_n @ u)
    order = np.argsort(tau)
    family_n, tau = family_n[order], tau[order]
    # The family's lines in their order across the image on three pitch lines in either order.
    picks = np.array(list(itertools.combinations(range(len(family_offsets_m)), 3)))
    c = np.concatenate([family_offsets_m[picks], family_offsets_m[picks][:, ::-1]])  # (T, 3)
    # tau_i (gamma c_i + 1) = alpha c_i + beta: three equations in (alpha, beta, gamma) per assignment.
    A = np.stack([c, np.ones_like(c), -c * tau[None, :]], axis=2)  # (T, 3, 3)
    with np.errstate(invalid="ignore", divide="ignore"):
        solvable = np.abs(np.linalg.det(A)) > 1e-12
        alpha, beta, gamma = np.moveaxis(np.linalg.solve(np.where(solvable[:, None, None], A, np.eye(3)),
                                                         np.broadcast_to(tau, c.shape)[..., None])[..., 0], 1, 0)
    horizon = cross3(v_a[None, :], gamma[:, None] * q[None, :] - alpha[:, None] * u[None, :])  # (T, 3)
    out = []
    for across in across_n:
        v_b = cross3(horizon, across)  # (T, 3)
        with np.errstate(invalid="ignore", divide="ignore"):
            f2 = -(v_b[:, :2] @ v_a[:2]) / (v_b[:, 2] * v_a[2])
            # The family's map c = a tau' + b in the pencil coordinate tau' = (l . q) / (l . v_b), affine (v_b is on
            # the horizon), least squares over its three lines.
            tau_f = (family_n @ q)[None, :] / (v_b @ family_n.T)  # (T, 3)
            tau_across = (across @ q) / (across @ v_a)
        t_mean, c_mean = tau_f.mean(axis=1, keepdims=True), c.mean(axis=1, keepdims=True)
        with np.errstate(invalid="ignore", divide="ignore"):
            a_f = ((tau_f - t_mean) * (c - c_mean)).sum(axis=1) / ((tau_f - t_mean) ** 2).sum(axis=1)
            b_f = c_mean[:, 0] - a_f * t_mean[:, 0]
            norm_a = np.sqrt((v_a[0] ** 2 + v_a[1] ** 2) / f2 + v_a[2] ** 2)  # |K^-1 v_a|
            norm_b = np.sqrt((v_b[:, 0] ** 2 + v_b[:, 1] ** 2) / f2 + v_b[:, 2] ** 2)
            # Equal norms of K^-1 h1 = -K^-1 v_x / a_y and K^-1 h2 = -K^-1 v_y / a_x: |a_across| |v_b| = |a_f| |v_a|.
            a_mag = np.abs(a_f) * norm_a / norm_b
        ok = solvable & (f2 > 0) & np.isfinite(a_mag) & np.isfinite(b_f) & np.isfinite(tau_across)
        if not ok.any():
            continue
        T, C, S = np.meshgrid(np.nonzero(ok)[0], np.arange(len(across_offsets_m)), (-1.0, 1.0), indexing="ij")
        T, C, S = T.ravel(), C.ravel(), S.ravel()
        a_across = S * a_mag[T]
        b_across = across_offsets_m[C] - a_across * tau_across
        family, other = (v_a, a_f[T], b_f[T]), (v_b[T], a_across, b_across)
        (v_x, a_x, b_x), (v_y, a_y, b_y) = (family, other) if a_is_x else (other, family)  # a_is_x: v_x = v_a
        H = homographies_from_maps(v_x, v_y, a_x, b_x, a_y, b_y)
        out.append(H[np.all(np.isfinite(H), axis=(1, 2))])
    return np.concatenate(out) if out else np.zeros((0, 3, 3))

