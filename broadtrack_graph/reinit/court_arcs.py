"""Court-model hypotheses from a circle's arc and the line across it, by rectifying the ground. No I/O.

A short arc (a penalty arc seen along a seventh of its circle, a zoomed view's piece of the centre circle) fixes a
free ellipse poorly: an ellipse fitted to it can be a third short of the circle's image, and the homographies built on
it (:mod:`.court_circle`) decompose into no plausible camera. Here the camera model is asked first. With the principal
point at the image centre, a focal length ``f``, a tilt and a roll, an image point's ray meets the ground of a camera
standing 1 m above it, looking along the pitch's x axis (pan 0), at

    q = Rx(tilt) Rz(roll) K^-1 (u, v, 1),   ground point (q_x / q_z, q_y / q_z)   (q_z > 0: below the horizon)

(SoccerNet's ``R_cw = (Rz(pan) Rx(tilt) Rz(roll))^T``, z down). Under the right ``f``, tilt and roll the arc's
points land on a circle of that plane, and the line across it lands at the chord's distance from its centre, in
radii (0 for the halfway line through the centre circle, 5.5 / 9.15 for a penalty arc's 16.5 m line). Every
(f, tilt) of a grid is tried at once for every arc (a circle fitted to the rectified points of each, algebraically,
its error in radii) and the lines' distances read for each; the best pairings of an arc, a line and a circle are
narrowed in tilt and roll (Levenberg-Marquardt, every place at once) along the valley of f
(:func:`arc_line_homographies`). What is left is a camera up to where it stands and which way it pans: the circle's
radius gives the height, the circle's centre and the foot of its chord place and turn it (``H = H0 S^-1``, S the
plane's similarity onto the pitch). The homographies go to the same gate, map score and fits as every other
hypothesis.

Image coordinates are normalised as in :mod:`.court_lines`: ``x_n = (u - W / 2) / s``, ``s = W / 2``. Pitch frame:
SoccerNet (metres, origin at the centre spot, z down).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.detect.marking_ellipses import ImageEllipse
from broadtrack_graph.detect.marking_structures import ImageLine
from broadtrack_graph.reinit.court_circle import CircleChord


@dataclass(frozen=True)
class CourtArcConfig:
    """Settings of :func:`arc_line_homographies`."""

    focal_steps: int = 28  # f / s on a geometric grid over the line gate's focal range ...
    tilt_range_deg: tuple[float, float] = (30.0, 89.5)  # ... and the tilt on an even grid (roll 0)
    tilt_steps: int = 40
    max_pairings: int = 8  # the arcs, lines and circles whose best place of the grid errs least ...
    coarse_max_error: float = 0.3  # ... and errs at most this there (radii: the arc off its circle, the line off
    #                                its chord, root mean square)
    max_error: float = 0.08  # a place kept errs at most this once narrowed ...
    valley_error: float = 0.02  # ... and at most this more than its pairing's best (the valley along f: docstring),
    coarse_valley_error: float = 0.05  # narrowed from the grid's places erring at most this more than its best
    narrow_rounds: int = 6  # Levenberg-Marquardt steps narrowing each place in tilt and roll (and f, for the best)
    arc_band_px: float = 4.0  # marking points this close to an arc (per 1280 px of width) are its points ...
    line_clear_px: float = 4.0  # ... unless this close to a long straight marking's stretch (its chord where they meet;
    line_clear_support_px: float = 160.0  # long: this many map pixels, per 1280 px; the Hough reads short straight
    #                                       pieces of an arc's own)
    min_arc_points: int = 12  # an arc with fewer points is not rectified, one with more than max_arc_points is
    max_arc_points: int = 48  # thinned to them
    min_sweep_deg: float = 20.0  # a rectified arc turning less than this about its centre is no circle's
    same_arc_share: float = 0.8  # an arc sharing this share of its points with one already taken is the same arc


def arc_points(ellipses: list[ImageEllipse], points_px: np.ndarray, lines: list[ImageLine], frame_width_px: int,
               config: CourtArcConfig = CourtArcConfig()) -> list[np.ndarray]:
    """The marking points (frame pixels) on each distinct arc: near its ellipse, clear of the straight markings.

    Args:
        ellipses: the map's ellipses and arcs (their fitted shape need only pass through the arc's points).
        points_px: (M, 2) the markings' centre points, frame pixels.
        lines: the map's straight markings (points near them are the line's, not the arc's).

    Returns:
        a list of (N_i, 2) arrays, one per distinct arc with at least ``min_arc_points`` points (thinned to
        ``max_arc_points``).
    """
    points_px = np.asarray(points_px, float).reshape(-1, 2)
    if not len(points_px) or not ellipses:
        return []
    unit = frame_width_px / 1280.0
    clear = np.ones(len(points_px), bool)
    for line in lines:
        if line.support_px < config.line_clear_support_px * unit:
            continue
        along = (points_px - line.centre_px) @ line.direction
        lo, hi = line.extent_px
        margin = 0.25 * (hi - lo)
        clear &= ((np.abs(points_px @ line.normal + line.offset_px) > config.line_clear_px * unit)
                  | (along < lo - margin) | (along > hi + margin))
    taken: list[np.ndarray] = []
    out = []
    for ellipse in ellipses:
        on = np.nonzero(clear & (ellipse.distances_px(points_px) <= config.arc_band_px * unit))[0]
        if len(on) < config.min_arc_points:
            continue
        if any(len(np.intersect1d(on, other, assume_unique=True)) >= config.same_arc_share * min(len(on), len(other))
               for other in taken):
            continue
        taken.append(on)
        chosen = on[np.linspace(0, len(on) - 1, min(len(on), config.max_arc_points)).astype(int)]
        out.append(points_px[chosen])
    return out


def arc_line_homographies(arcs_px: list[np.ndarray], lines: list[ImageLine], frame_size, circles: list[CircleChord],
                          focal_range_n: tuple[float, float], config: CourtArcConfig = CourtArcConfig()
                          ) -> np.ndarray:
    """(K, 3, 3) ground homographies (pitch (x, y, 1) metres -> normalised image points) putting a pitch circle on
    each arc's points and its chord on a straight marking (module docstring).

    The arc and its chord fix the tilt and the roll well and the focal length poorly: the error's valley runs along
    f, and on a short arc its floor varies by less than a pixel's worth. So every f of the grid is kept whose valley
    floor is within ``valley_error`` of the pairing's best (each narrowed in tilt and roll), with the best narrowed in
    f too; the map's score, which reads every marking in view, chooses among them.

    Args:
        arcs_px: the arcs' points (:func:`arc_points`), frame pixels.
        lines: the straight markings (their two ends, frame pixels, place each).
        circles: the pitch circles with their chords (:func:`~.court_circle.pitch_circle_chords`).
        focal_range_n: (lo, hi) of f / s searched (s = W / 2).
    """
    if not arcs_px or not lines:
        return np.zeros((0, 3, 3))
    W, H = frame_size
    s, centre = W / 2.0, np.array([W / 2.0, H / 2.0])
    ends_n = (np.array([line.ends_px() for line in lines]) - centre) / s  # (L, 2, 2)
    shares = np.array([abs(c.chord_x_m - c.centre_x_m) / c.radius_m for c in circles])
    focal = np.geomspace(*focal_range_n, config.focal_steps)
    tilt = np.radians(np.linspace(*config.tilt_range_deg, config.tilt_steps))
    grid = np.stack(np.meshgrid(focal, tilt, [0.0], indexing="ij"), axis=-1).reshape(-1, 3)  # (G, 3)
    arcs_n = [(np.asarray(points_px, float) - centre) / s for points_px in arcs_px]
    pairings = []  # (best coarse error, arc, line, circle, (F,) best tilt per f, (F,) its error)
    for a, arc_n in enumerate(arcs_n):
        table = _errors(grid, arc_n, ends_n, shares, config.min_sweep_deg)  # (G, L, C)
        table = table.reshape(len(focal), len(tilt), len(lines), len(circles))
        best_tilt = np.argmin(table, axis=1)  # (F, L, C)
        floor = np.min(table, axis=1)
        for line, circle in zip(*np.nonzero(np.isfinite(floor).any(axis=0))):
            rows = floor[:, line, circle]
            pairings.append((float(rows.min()), a, line, circle, tilt[best_tilt[:, line, circle]], rows))
    pairings = [p for p in sorted(pairings, key=lambda p: p[0])[:config.max_pairings]
                if p[0] <= config.coarse_max_error]
    out = []
    for a in sorted({p[1] for p in pairings}):
        mine = [p for p in pairings if p[1] == a]
        rows = [(k, i) for k, p in enumerate(mine) for i in np.nonzero(p[5] <= p[0] + config.coarse_valley_error)[0]]
        if not rows:
            continue
        place = np.array([[focal[i], mine[k][4][i], 0.0] for k, i in rows])
        line = np.array([mine[k][2] for k, _ in rows])
        circle = np.array([mine[k][3] for k, _ in rows])
        place, error = _narrowed(place, arcs_n[a], ends_n[line], shares[circle], (False, True, True), focal_range_n,
                                 config)
        owner = np.array([k for k, _ in rows])
        bests = [own[np.argmin(error[own])] for own in (np.nonzero(owner == k)[0] for k in range(len(mine)))]
        bests = np.array([b for b in bests if error[b] <= config.max_error], int)
        if not len(bests):
            continue
        finest, finest_error = _narrowed(place[bests], arcs_n[a], ends_n[line[bests]], shares[circle[bests]],
                                         (True, True, True), focal_range_n, config)
        kept = [np.nonzero((owner == owner[b]) & (error <= min(config.max_error, error[b] + config.valley_error)))[0]
                for b in bests]  # the valley of each pairing
        kept = np.concatenate(kept)
        places = np.vstack([place[kept], finest[finest_error <= config.max_error]])
        index = np.concatenate([kept, bests[finest_error <= config.max_error]])
        out.append(_homographies(places, arcs_n[a], ends_n[line[index]], [circles[k] for k in circle[index]]))
    return np.concatenate(out) if out else np.zeros((0, 3, 3))


def pieces_of(arc_px: np.ndarray, lines: list[ImageLine], band_px: float, samples: int = 5) -> np.ndarray:
    """(L,) bool: the straight markings lying along the arc (frame pixels): ``samples`` points along each, every one
    within twice ``band_px`` of the arc's points (and half the gap between two of them). A straight piece of an arc
    lies one radius from its circle's centre, as no line the arc is paired with need."""
    arc_px = np.asarray(arc_px, float)
    if not lines:
        return np.zeros(0, bool)
    gap = np.median(np.linalg.norm(np.diff(arc_px, axis=0), axis=1)) if len(arc_px) > 1 else 0.0
    t = np.linspace(0.0, 1.0, samples)
    ends = np.array([line.ends_px() for line in lines], float)  # (L, 2, 2)
    along = ends[:, :1] + t[None, :, None] * (ends[:, 1:] - ends[:, :1])  # (L, S, 2)
    nearest = np.min(np.linalg.norm(along[:, :, None] - arc_px[None, None], axis=-1), axis=2)  # (L, S)
    return (nearest <= 2.0 * band_px + 0.5 * gap).all(axis=1)


def rectifiers(params: np.ndarray) -> np.ndarray:
    """(G, 3, 3) ``Rx(tilt) Rz(roll) K^-1`` of (G, 3) (f / s, tilt, roll): normalised image point -> the ground's
    homogeneous point under a camera 1 m up at the origin, pan 0. Written out: ``Rx Rz = [[cr, -sr, 0], [ct sr,
    ct cr, -st], [st sr, st cr, ct]]``, its first two columns over f."""
    f, t, r = params[:, 0], params[:, 1], params[:, 2]
    ct, st, cr, sr = np.cos(t), np.sin(t), np.cos(r), np.sin(r)
    inv_f = 1 / f
    out = np.empty((len(params), 3, 3))
    out[:, 0, 0], out[:, 0, 1], out[:, 0, 2] = cr * inv_f, -sr * inv_f, 0.0
    out[:, 1, 0], out[:, 1, 1], out[:, 1, 2] = (ct * sr) * inv_f, (ct * cr) * inv_f, -st
    out[:, 2, 0], out[:, 2, 1], out[:, 2, 2] = (st * sr) * inv_f, (st * cr) * inv_f, ct
    return out


def on_ground(rectifiers: np.ndarray, points_n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(G, N, 2) ground points of normalised image points, (N, 2) for every rectifier or (G, N, 2) one set each,
    under each rectifier (G, 3, 3), and (G, N) whether below the horizon."""
    x, y = points_n[..., 0], points_n[..., 1]
    if x.ndim == 1:
        x, y = x[None], y[None]
    qx, qy, qz = (rectifiers[:, i, 0:1] * x + rectifiers[:, i, 1:2] * y + rectifiers[:, i, 2:3] for i in range(3))
    below = qz > 1e-9
    qz = np.where(below, qz, 1.0)
    return np.stack([qx / qz, qy / qz], axis=-1), below


def fitted_circles(ground: np.ndarray, valid: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Circles fitted algebraically to (G, N, 2) points (the invalid ones left out): centres (G, 2), radii (G,) and
    the points' distances off them in radii (G, N) (NaN where the fit fails)."""
    w = valid.astype(float)
    x, y = ground[..., 0] * w, ground[..., 1] * w
    z = x * x + y * y
    n, sx, sy = w.sum(axis=1), x.sum(axis=1), y.sum(axis=1)
    sxx, sxy, syy = (x * x).sum(axis=1), (x * y).sum(axis=1), (y * y).sum(axis=1)
    AtA = np.stack([np.stack([sxx, sxy, sx], -1), np.stack([sxy, syy, sy], -1), np.stack([sx, sy, n], -1)], 1)
    Atb = -np.stack([(x * z).sum(axis=1), (y * z).sum(axis=1), z.sum(axis=1)], -1)
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        solvable = (n >= 3) & np.isfinite(AtA).all(axis=(1, 2)) & (np.abs(np.linalg.det(AtA)) > 1e-300)
        sol = np.full((len(AtA), 3), np.nan)
        sol[solvable] = np.linalg.solve(AtA[solvable], Atb[solvable][..., None])[..., 0]
        c = -0.5 * sol[:, :2]
        r2 = c[:, 0] ** 2 + c[:, 1] ** 2 - sol[:, 2]
        r = np.sqrt(np.where(r2 > 0, r2, np.nan))
        off = (np.hypot(ground[..., 0] - c[:, :1], ground[..., 1] - c[:, 1:]) - r[:, None]) / r[:, None]
    return c, r, off


def _residuals(params: np.ndarray, arc_n: np.ndarray, ends_n: np.ndarray, shares: np.ndarray, min_sweep_deg: float
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """How far each place (G, 3) is from putting the arc on a circle and line l at circle c's chord, in radii: the
    arc's points off their circle (G, N), the line off the chord (G, L, C) and where both count (G, L, C): not where
    the arc or the line's ends are above the horizon, the arc turns less than ``min_sweep_deg`` about its centre, or
    a penalty arc lies on its centre's side of its chord.

    Args:
        ends_n: the lines' two ends, normalised: (L, 2, 2) for every place, or (G, L, 2, 2) one set each.
        shares: the chords' distances from their circles' centres in radii: (C,), or (G, 1, C) one set each.
    """
    off, _, r, arc_ok, turned, _, distance, arc_side, line_below = rectified(params, arc_n, ends_n)
    beyond = -np.sign(distance) * arc_side  # > 0: the arc is on the far side of the line from the centre
    radius = np.where(np.isfinite(r), r, 1.0)[:, None]
    line_off = (np.abs(distance) / radius)[..., None] - shares  # (G, L, C)
    far_side = (beyond > 0)[..., None] | (shares < 1e-9)
    ok = (arc_ok & (turned >= math.radians(min_sweep_deg)))[:, None, None] & line_below[..., None] & far_side
    return np.where(np.isfinite(off), off, 0.0), line_off, ok


def rectified(params: np.ndarray, arc_n: np.ndarray, ends_n: np.ndarray):
    """An arc's points (N, 2) and straight markings' ends (L, 2, 2) for every place, or (G, L, 2, 2) one set each,
    normalised, put on the ground of each place (G, 3) (:func:`rectifiers`): the arc's points off the circle fitted to
    them (G, N, in radii), its centre (G, 2; 0 where the fit fails), its radius (G,), whether the arc counts (its
    points below the horizon and the fit finite, (G,)), the angle it turns through about its centre (G,), each line's
    unit normal (G, L, 2), the centre's signed distance from it along that normal (G, L), the arc's mean point's
    offset from it along that normal (G, L) and whether its two ends are below the horizon (G, L)."""
    G, L = len(params), ends_n.shape[-3]
    rect = rectifiers(params)
    ground, below = on_ground(rect, arc_n)
    c, r, off = fitted_circles(ground, below)
    arc_ok = below.all(axis=1) & np.isfinite(r) & np.isfinite(off).all(axis=1)
    centre = np.where(np.isfinite(c), c, 0.0)
    turned = arc_sweep(ground - centre[:, None], arc_ok)
    line_ground, line_below = on_ground(rect, ends_n.reshape(*ends_n.shape[:-3], -1, 2))
    line_ground = line_ground.reshape(G, L, 2, 2)
    along = line_ground[:, :, 1] - line_ground[:, :, 0]
    normal = np.stack([-along[..., 1], along[..., 0]], -1)
    normal /= np.maximum(np.linalg.norm(normal, axis=-1, keepdims=True), 1e-12)
    distance = np.einsum("gli,gli->gl", centre[:, None] - line_ground[:, :, 0], normal)  # signed, centre to line
    # The arc's side of the line (its points' mean offset from it) against the centre's.
    mean_arc = np.where(below[..., None], ground, 0.0).sum(axis=1) / np.maximum(below.sum(axis=1), 1)[:, None]
    arc_side = np.einsum("gi,gli->gl", mean_arc, normal) - np.einsum("gli,gli->gl", line_ground[:, :, 0], normal)
    return off, centre, r, arc_ok, turned, normal, distance, arc_side, line_below.reshape(G, L, 2).all(axis=2)


def _errors(params: np.ndarray, arc_n: np.ndarray, ends_n: np.ndarray, shares: np.ndarray, min_sweep_deg: float
            ) -> np.ndarray:
    """(G, L, C) the root mean square of :func:`_residuals`' two kinds (the arc's mean square and the line's square
    summed), inf where they do not count."""
    off, line_off, ok = _residuals(params, arc_n, ends_n, shares, min_sweep_deg)
    error = np.sqrt(np.mean(off**2, axis=1)[:, None, None] + line_off**2)
    return np.where(ok, error, np.inf)


def arc_sweep(offsets: np.ndarray, valid: np.ndarray) -> np.ndarray:
    """(G,) the angle (radians) the points (G, N, 2), relative to their circle's centre, turn through (0 where
    invalid): a full turn less the largest gap between neighbouring angles."""
    angles = np.sort(np.arctan2(offsets[..., 1], offsets[..., 0]), axis=1)
    gaps = np.diff(np.concatenate([angles, angles[:, :1] + 2 * math.pi], axis=1), axis=1)
    return np.where(valid, 2 * math.pi - gaps.max(axis=1), 0.0)


def _narrowed(place: np.ndarray, arc_n: np.ndarray, ends_n: np.ndarray, shares: np.ndarray, free: tuple,
              focal_range_n: tuple[float, float], config: CourtArcConfig) -> tuple[np.ndarray, np.ndarray]:
    """Places (P, 3) of one arc, each with its own line's ends (P, 2, 2) and chord share (P,), narrowed by
    Levenberg-Marquardt steps in the ``free`` parameters (log f, tilt, roll; forward-difference Jacobians), every place
    at once, f kept in ``focal_range_n``: (P, 3) places and (P,) errors (:func:`_errors`)."""
    N = len(arc_n)
    free_axes = [k for k, is_free in enumerate(free) if is_free]
    ends_each, shares_each = ends_n[:, None], shares[:, None, None]

    def residuals(x: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # (P, N + 1) scaled to sum to the error squared
        copies = len(x) // len(place)  # x: the places' parameters, stacked that many times
        off, line_off, ok = _residuals(np.column_stack([np.exp(x[:, 0]), x[:, 1:]]), arc_n,
                                       np.tile(ends_each, (copies, 1, 1, 1)), np.tile(shares_each, (copies, 1, 1)),
                                       config.min_sweep_deg)
        return np.column_stack([off / math.sqrt(N), line_off[:, 0, 0]]), ok[:, 0, 0]

    return narrowed(np.column_stack([np.log(place[:, 0]), place[:, 1:]]), residuals, free_axes, config.narrow_rounds,
                    focal_range_n)


def narrowed(x: np.ndarray, residuals, free_axes: list[int], rounds: int, focal_range_n: tuple[float, float]
             ) -> tuple[np.ndarray, np.ndarray]:
    """Places x (P, 3) as (log f / s, tilt, roll) narrowed by ``rounds`` Levenberg-Marquardt steps in ``free_axes``
    (forward-difference Jacobians), every place at once, f kept in ``focal_range_n``; ``residuals(x)`` gives (P, R)
    residuals and (P,) whether they count, and for k copies of the places stacked (k P, 3) theirs in that order (a
    trial's residuals and its Jacobian's shifted places are asked in one call; a trial not taken leaves the Jacobian
    where it was). Returns (P, 3) places as (f / s, tilt, roll) and (P,) root sum square errors (inf where they do
    not count)."""
    step = 1e-6
    shifts = [step * np.eye(3)[k] for k in free_axes]

    def with_jacobian(x: np.ndarray, jacobian: bool = True):  # (P, R) residuals, (P,) counted, (P, R, F) or None
        r, ok = residuals(np.concatenate([x] + [x + shift for shift in shifts]) if jacobian else x)
        if not jacobian:
            return r, ok, None
        r = r.reshape(1 + len(free_axes), len(x), -1)
        J = ((r[1:] - r[0]) / step).transpose(1, 2, 0)
        return r[0], ok[:len(x)], np.ascontiguousarray(J)  # J laid out as the einsums below have always read it

    r, ok, J = with_jacobian(x)
    cost = np.where(ok, np.sum(r**2, axis=1), np.inf)
    damping = np.full(len(x), 1e-3)
    for round_index in range(rounds):
        JtJ = np.einsum("pnf,png->pfg", J, J)
        Jtr = np.einsum("pnf,pn->pf", J, r)
        scaled = JtJ + damping[:, None, None] * (np.eye(len(free_axes)) * (np.diagonal(JtJ, axis1=1, axis2=2)[
            :, :, None] + 1e-12))
        with np.errstate(invalid="ignore"):
            delta = -np.linalg.solve(scaled, Jtr[..., None])[..., 0]
        trial = x.copy()
        trial[:, free_axes] += np.where(np.isfinite(delta), delta, 0.0)
        trial[:, 0] = np.clip(trial[:, 0], *np.log(focal_range_n))
        r_trial, ok_trial, J_trial = with_jacobian(trial, jacobian=round_index < rounds - 1)
        cost_trial = np.where(ok_trial, np.sum(r_trial**2, axis=1), np.inf)
        better = cost_trial < cost
        x = np.where(better[:, None], trial, x)
        r = np.where(better[:, None], r_trial, r)
        cost = np.where(better, cost_trial, cost)
        J = J if J_trial is None else np.where(better[:, None, None], J_trial, J)
        damping = np.where(better, damping / 3.0, damping * 4.0)
    return np.column_stack([np.exp(x[:, 0]), x[:, 1:]]), np.sqrt(cost)


def _homographies(places: np.ndarray, arc_n: np.ndarray, ends_n: np.ndarray, circles: list[CircleChord]
                  ) -> np.ndarray:
    """(K, 3, 3) the homographies (pitch metres -> normalised image) of places (Q, 3) of one arc, each with its line's
    ends (Q, 2, 2) and its circle: ``H0 = (Rx(tilt) Rz(roll) K^-1)^-1`` times the inverse of the similarity taking
    the rectified plane onto the pitch (the circle's centre onto its centre, the chord's foot onto its side; a
    diameter's line along the halfway line, either way round: two each)."""
    rect = rectifiers(places)
    ground, below = on_ground(rect, arc_n)
    c, r, _ = fitted_circles(ground, below)
    ends, _ = on_ground(rect, ends_n)  # (Q, 2, 2)
    along = ends[:, 1] - ends[:, 0]
    along /= np.maximum(np.linalg.norm(along, axis=1, keepdims=True), 1e-12)
    foot = ends[:, 0] + np.einsum("qi,qi->q", c - ends[:, 0], along)[:, None] * along
    radius = np.array([circle.radius_m for circle in circles])
    chord_side = np.array([np.sign(circle.chord_x_m - circle.centre_x_m) for circle in circles])
    world_centre = np.array([[circle.centre_x_m, 0.0] for circle in circles])
    # The turn alpha taking the foot's direction from the centre onto the chord's side (+-x), or the line's direction
    # onto +-y for a diameter (both).
    towards = np.arctan2(foot[:, 1] - c[:, 1], foot[:, 0] - c[:, 0])
    line_angle = np.arctan2(along[:, 1], along[:, 0])
    diameter = chord_side == 0
    first = np.where(diameter, math.pi / 2 - line_angle, np.where(chord_side > 0, 0.0, math.pi) - towards)
    alpha = np.concatenate([first, (-math.pi / 2 - line_angle)[diameter]])
    which = np.concatenate([np.arange(len(places)), np.nonzero(diameter)[0]])
    return placed_homographies(rect[which], c[which], alpha, radius[which] / r[which], world_centre[which])


def placed_homographies(rect: np.ndarray, centre: np.ndarray, alpha: np.ndarray, scale: np.ndarray,
                        world_centre: np.ndarray) -> np.ndarray:
    """(K, 3, 3) ground homographies (pitch metres -> normalised image, unit norm; the non-finite left out) of K
    rectified planes (their rectifiers (K, 3, 3)), each taken onto the pitch by the similarity turning it by ``alpha``
    (K,) and scaling it by ``scale`` (K,) about its circle's centre (K, 2), which lands on ``world_centre`` (K, 2):
    ``H = H0 S^-1`` with ``H0 = rect^-1``."""
    ca, sa = np.cos(alpha), np.sin(alpha)
    cx, cy = centre[:, 0], centre[:, 1]
    S = np.zeros((len(alpha), 3, 3))
    S[:, 0, 0], S[:, 0, 1], S[:, 1, 0], S[:, 1, 1] = scale * ca, -scale * sa, scale * sa, scale * ca
    S[:, 0, 2] = world_centre[:, 0] - scale * (ca * cx - sa * cy)
    S[:, 1, 2] = world_centre[:, 1] - scale * (sa * cx + ca * cy)
    S[:, 2, 2] = 1.0
    with np.errstate(invalid="ignore", divide="ignore"):
        H = np.linalg.solve(np.swapaxes(S, 1, 2), np.swapaxes(np.linalg.inv(rect), 1, 2))
        H = np.swapaxes(H, 1, 2)  # H0 S^-1
        H /= np.linalg.norm(H, axis=(1, 2), keepdims=True)
    return H[np.isfinite(H).all(axis=(1, 2))]
