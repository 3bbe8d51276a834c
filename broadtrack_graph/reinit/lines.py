"""Re-initialisation from per-class line points (a learned detector, or annotations), no history.

:func:`reinit_from_lines` forms hypotheses, refines each with :func:`fit_camera_to_lines` and
keeps the best-scoring (:func:`~broadtrack_graph.reinit.scoring.score_labelled`): a homography
from >= 4 straight-line correspondences when there are enough (:func:`homography_from_lines`,
:func:`camera_from_homography`), and a global pan/tilt/f search at each candidate tripod
position (:func:`global_search_labelled`; the default tripods, then their mirror images).

Conventions: pitch frame in metres, origin at the centre spot, z down (a camera above the pitch
has z < 0); pan 0 looks towards -y, positive pan turns towards +x. No I/O.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from broadtrack_graph.geometry.camera import Camera, angles_from_rotation
from broadtrack_graph.geometry.matrices import cross3
from broadtrack_graph.geometry.pitch import Arc, PitchTemplate, Segment
from broadtrack_graph.geometry.template import TemplateCurves, TemplateSampling
from broadtrack_graph.reinit.linefit import LineFitConfig, fit_camera_to_lines
from broadtrack_graph.reinit.positions import (
    candidate_positions,
    facing_pan_rad,
    mirrored_position,
)
from broadtrack_graph.reinit.scoring import LabelledScore, ReinitResult, score_labelled

# --------------------------------------------------------------------------- homography


def _fit_image_line(points_px: np.ndarray) -> np.ndarray | None:
    """Homogeneous line (a, b, c), a^2 + b^2 = 1, through (N >= 2) points by total least squares."""
    if len(points_px) < 2:
        return None
    centre = points_px.mean(axis=0)
    _, s, vt = np.linalg.svd(points_px - centre)
    if s[0] < 1.0:  # all points within a pixel: no direction
        return None
    normal = vt[1]
    return np.array([normal[0], normal[1], -normal @ centre])


def _cross_matrix(v: np.ndarray) -> np.ndarray:
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def homography_from_lines(lines_px: dict[str, np.ndarray], pitch: PitchTemplate) -> np.ndarray | None:
    """Plane-to-image homography (pitch (x, y, 1) metres -> pixels) from straight ground lines.

    Each straight ground class with >= 2 points gives one line correspondence
    (``L_w ~ H^T l_img``); a normalised DLT needs 4 lines, not 3 through one point
    (parallel lines meet at infinity). Lens distortion is ignored here.

    Returns:
        (3, 3) homography or None when fewer than 4 usable lines / degenerate.
    """
    image_lines, world_lines = [], []
    for name, points in lines_px.items():
        element = pitch.elements.get(name)
        if not isinstance(element, Segment) or not pitch.is_on_ground(name):
            continue
        line = _fit_image_line(np.asarray(points, dtype=float))
        if line is None:
            continue
        world = cross3([*element.start_w[:2], 1.0], [*element.end_w[:2], 1.0])
        image_lines.append(line)
        world_lines.append(world / np.linalg.norm(world[:2]))
    if len(image_lines) < 4:
        return None
    directions = {(round(abs(w[0]), 3), round(abs(w[1]), 3)) for w in world_lines}
    if len(directions) < 2:
        return None
    all_points = np.vstack([np.asarray(p, float) for p in lines_px.values()])
    centre, scale = all_points.mean(axis=0), max(all_points.std(), 1.0)
    T_i = np.array([[1 / scale, 0, -centre[0] / scale], [0, 1 / scale, -centre[1] / scale], [0, 0, 1]])
    T_w = np.diag([1 / 30.0, 1 / 30.0, 1.0])
    rows = []
    for l_img, l_w in zip(image_lines, world_lines):
        ln = np.linalg.inv(T_i).T @ l_img
        Lw = np.linalg.inv(T_w).T @ l_w
        N = np.zeros((3, 9))
        for b in range(3):
            for a in range(3):
                N[b, 3 * a + b] = ln[a]
        rows.append(_cross_matrix(Lw / np.linalg.norm(Lw)) @ N)
    A = np.vstack(rows)
    _, s, vt = np.linalg.svd(A)
    if s[-2] < 1e-9 * s[0]:
        return None
    Hn = vt[-1].reshape(3, 3)
    H = np.linalg.inv(T_i) @ Hn @ T_w
    return H / np.linalg.norm(H)


def camera_from_homography(H: np.ndarray, width_px: int, height_px: int, reference_points_w=None) -> Camera | None:
    """Decompose a pitch-plane homography into a camera (principal point at the centre, k1 0).

    The focal length comes from the orthogonality / equal-norm constraints on the first
    two columns of K^-1 H; the sign is chosen so that the reference points (default: the
    centre spot) are in front of the camera.

    Returns:
        The camera, or None when f cannot be recovered or the camera would be under the pitch.
    """
    shift = np.array([[1.0, 0, -width_px / 2.0], [0, 1.0, -height_px / 2.0], [0, 0, 1.0]])
    G = shift @ H
    h1, h2 = G[:, 0], G[:, 1]
    estimates = []
    den = h1[2] * h2[2]
    if abs(den) > 1e-12:
        f2 = -(h1[0] * h2[0] + h1[1] * h2[1]) / den
        if f2 > 0:
            estimates.append(f2)
    den = h2[2] ** 2 - h1[2] ** 2
    if abs(den) > 1e-12:
        f2 = (h1[0] ** 2 + h1[1] ** 2 - h2[0] ** 2 - h2[1] ** 2) / den
        if f2 > 0:
            estimates.append(f2)
    if not estimates:
        return None
    focal = math.sqrt(float(np.median(estimates)))
    if not (0.1 * width_px < focal < 30 * width_px):
        return None
    A = np.diag([1 / focal, 1 / focal, 1.0]) @ G
    scale = 2.0 / (np.linalg.norm(A[:, 0]) + np.linalg.norm(A[:, 1]))
    reference = np.zeros((1, 3)) if reference_points_w is None else np.asarray(reference_points_w, float).reshape(-1, 3)
    for sign in (1.0, -1.0):
        r1, r2, t = sign * scale * A[:, 0], sign * scale * A[:, 1], sign * scale * A[:, 2]
        M = np.column_stack([r1, r2, cross3(r1, r2)])
        u, _, vt = np.linalg.svd(M)
        R = u @ vt
        if np.linalg.det(R) < 0:
            continue
        depth = (reference[:, :2] @ np.column_stack([r1, r2]).T + t)[:, 2]
        if np.median(depth) <= 0:
            continue
        C = -R.T @ t
        if C[2] >= 0:
            return None  # under the pitch: labels inconsistent with a real camera
        pan, tilt, roll = angles_from_rotation(R)
        return Camera(focal, 0.0, pan, tilt, roll, C, width_px, height_px)
    return None


# --------------------------------------------------------------------------- global search (labelled)


def _rays_world(pans, tilts, rays_c):
    """World rays for every (pan, tilt) with roll 0: (P, T, M, 3) from camera rays (M, 3)."""
    cp, sp = np.cos(pans)[:, None, None], np.sin(pans)[:, None, None]
    ct, st = np.cos(tilts)[None, :, None], np.sin(tilts)[None, :, None]
    x, y, z = rays_c[:, 0], rays_c[:, 1], rays_c[:, 2]
    y1 = ct * y - st * z  # Rx(tilt)
    z1 = st * y + ct * z
    x1 = np.broadcast_to(x, y1.shape)
    xw = cp * x1 - sp * y1  # Rz(pan)
    yw = sp * x1 + cp * y1
    return xw, yw, np.broadcast_to(z1, xw.shape)


def _segment_distance_2d(px, py, a, b):
    dx, dy = b[0] - a[0], b[1] - a[1]
    length2 = max(dx * dx + dy * dy, 1e-12)
    t = np.clip(((px - a[0]) * dx + (py - a[1]) * dy) / length2, 0.0, 1.0)
    return np.hypot(px - a[0] - t * dx, py - a[1] - t * dy)


def _element_distance_m(element, C, xw, yw, zw):
    """Distance (metres) from where each ray meets the element's plane to the element, and the depth."""
    big = np.full(xw.shape, np.inf)
    if isinstance(element, Arc) or element.start_w[2] == element.end_w[2] == 0.0:
        with np.errstate(divide="ignore", invalid="ignore"):
            s = (0.0 - C[2]) / zw
        ok = s > 0
        gx, gy = C[0] + s * xw, C[1] + s * yw
        if isinstance(element, Arc):
            d = np.abs(np.hypot(gx - element.centre_w[0], gy - element.centre_w[1]) - element.radius_m)
        else:
            d = _segment_distance_2d(gx, gy, element.start_w[:2], element.end_w[:2])
        return np.where(ok, d, big), np.where(ok, s, 1.0)
    # Goal elements lie in the plane x = start_x.
    x0 = element.start_w[0]
    with np.errstate(divide="ignore", invalid="ignore"):
        s = (x0 - C[0]) / xw
    ok = s > 0
    gy, gz = C[1] + s * yw, C[2] + s * zw
    d = _segment_distance_2d(gy, gz, element.start_w[1:], element.end_w[1:])
    return np.where(ok, d, big), np.where(ok, s, 1.0)


@dataclass(frozen=True)
class SearchGrid:
    """The global search grid (angles relative to facing the centre spot)."""

    pan_half_range_deg: float = 75.0
    pan_step_deg: float = 3.0
    tilt_min_deg: float = 45.0
    tilt_max_deg: float = 89.0
    tilt_step_deg: float = 2.5
    focal_min_per_width: float = 0.45  # f / W: about 96 deg horizontal field of view
    focal_max_per_width: float = 9.0  # about 6 deg
    focal_count: int = 11
    points_per_class: int = 5  # labelled points used per class in the search


def global_search_labelled(lines_px: dict[str, np.ndarray], position_w, width_px: int, height_px: int,
                           pitch: PitchTemplate, grid: SearchGrid = SearchGrid(), top_k: int = 3,
                           robust_px: float = 15.0) -> list[tuple[float, Camera]]:
    """Best (pan, tilt, f) cameras at a fixed focal point for per-class points (roll 0, k1 0).

    Each point's viewing ray is cut with its element's plane (the ground, or the goal
    plane x = +-52.5) and its distance to the element, converted to pixels by f / depth,
    enters a Cauchy cost. Vectorised over the whole grid.

    Returns:
        Up to top_k (cost, camera) pairs, best first, from distinct grid cells.
    """
    C = np.asarray(position_w, dtype=float)
    names, points = [], []
    for name, pts in lines_px.items():
        if name not in pitch.elements or not len(pts):
            continue
        pts = np.asarray(pts, float)
        if len(pts) > grid.points_per_class:
            pts = pts[np.linspace(0, len(pts) - 1, grid.points_per_class).round().astype(int)]
        names.append(name)
        points.append(pts)
    if not names:
        return []
    centre_pan = facing_pan_rad(C)
    pans = centre_pan + np.radians(np.arange(-grid.pan_half_range_deg, grid.pan_half_range_deg + 1e-9, grid.pan_step_deg))
    tilts = np.radians(np.arange(grid.tilt_min_deg, grid.tilt_max_deg + 1e-9, grid.tilt_step_deg))
    focals = width_px * np.geomspace(grid.focal_min_per_width, grid.focal_max_per_width, grid.focal_count)
    principal = np.array([width_px / 2.0, height_px / 2.0])
    costs = np.zeros((len(focals), len(pans), len(tilts)))
    for i, f in enumerate(focals):
        for name, pts in zip(names, points):
            rays_c = np.column_stack([(pts - principal) / f, np.ones(len(pts))])
            xw, yw, zw = _rays_world(pans, tilts, rays_c)
            d_m, depth = _element_distance_m(pitch.elements[name], C, xw, yw, zw)
            d_px = np.minimum(d_m * f / depth, 1e4)
            costs[i] += np.sum(np.log1p((d_px / robust_px) ** 2), axis=2)
    order = np.argsort(costs, axis=None)
    picked: list[tuple[float, Camera]] = []
    used: list[tuple[int, int, int]] = []
    for flat in order:
        i, p, t = np.unravel_index(flat, costs.shape)
        if any(abs(i - a) <= 2 and abs(p - b) <= 3 and abs(t - c) <= 3 for a, b, c in used):
            continue
        used.append((i, p, t))
        picked.append((float(costs[i, p, t]), Camera(focals[i], 0.0, pans[p], tilts[t], 0.0, C, width_px, height_px)))
        if len(picked) >= top_k:
            break
    return picked


# --------------------------------------------------------------------------- re-initialisation from lines


@dataclass(frozen=True)
class ReinitConfig:
    """Settings of :func:`reinit_from_lines`."""

    tau_px: float = 5.0  # threshold of the per-class score
    good_enough_max_px: float = 4.0  # stop trying hypotheses once a refined one has every point this close ...
    good_enough_inlier_share: float = 0.97  # ... or this share of points within tau_px
    search_top_k: int = 3  # hypotheses kept per candidate position
    polished: int = 2  # the best this many refined hypotheses get the final max-error polish
    coarse_iterations: int = 30  # LM iterations when refining a hypothesis for ranking
    max_refined: int = 4  # at most this many search hypotheses are refined (best search cost first)
    position_sigma_m: float = 8.0  # prior on the focal point around a candidate position
    grid: SearchGrid = SearchGrid()  # the global search grid


@dataclass(frozen=True)
class _Ranked:
    """A fitted hypothesis of :func:`reinit_from_lines`: its rank key (:func:`_rank_key`, higher is better), the order
    it was tried in (the later first on a tie), the camera, its score, where it came from and its focal point's prior
    (metres, or None)."""

    key: tuple
    order: int
    camera: Camera
    score: LabelledScore
    label: str
    prior: np.ndarray | None


def _rank_key(score: LabelledScore, cost: float):
    return (score.jaccard, score.inlier_share, -score.mean_distance_px, -cost)


def reinit_from_lines(
    lines_px: dict[str, np.ndarray],
    width_px: int,
    height_px: int,
    pitch: PitchTemplate | None = None,
    positions_w=None,
    config: ReinitConfig = ReinitConfig(),
    curves: TemplateCurves | None = None,
    sampling: TemplateSampling | None = None,
    fit_config: LineFitConfig | None = None,
) -> ReinitResult:
    """A camera from per-class marking points alone (several hypotheses, the best refined one kept).

    Hypotheses, in order: the homography of >= 4 straight ground lines; then a global
    search at each candidate focal point (positions_w, default: the default tripods and
    their mirrors). Each is refined by :func:`fit_camera_to_lines` and scored by
    :func:`score_labelled`; the search stops early when a hypothesis fits every class.

    Args:
        lines_px: class name -> (M, 2) pixels.
        positions_w: candidate focal points (metres); None = :func:`candidate_positions`.

    Returns:
        ReinitResult; camera None (with a reason) when no class is usable.
    """
    pitch = pitch or PitchTemplate()
    curves = curves or TemplateCurves(pitch)
    sampling = sampling or TemplateSampling(pitch)
    fit_config = fit_config or LineFitConfig()
    lines_px = {n: np.asarray(p, float).reshape(-1, 2) for n, p in lines_px.items() if n in pitch.elements and len(p)}
    if not lines_px:
        return ReinitResult(None, None, "", "no labelled point of a known class")
    ranked: list[_Ranked] = []
    tried = 0
    coarse_config = replace(fit_config, polish_power=0.0, iterations=config.coarse_iterations)

    def consider(initial: Camera, label: str, prior):
        nonlocal tried
        tried += 1
        fit = fit_camera_to_lines(initial, lines_px, curves, coarse_config, position_prior_w=prior)
        score = score_labelled(fit.camera, lines_px, config.tau_px, sampling)
        ranked.append(_Ranked(_rank_key(score, fit.cost), tried, fit.camera, score, label, prior))
        return fit.max_distance_px < config.good_enough_max_px or score.inlier_share >= config.good_enough_inlier_share

    def finish() -> ReinitResult:
        if not ranked:
            return ReinitResult(None, None, "", "no hypothesis could be formed", tried)
        ranked.sort(key=lambda item: (item.key, item.order), reverse=True)
        best = ranked[0]
        if fit_config.polish_power > 2:
            for item in ranked[: config.polished]:
                fit = fit_camera_to_lines(item.camera, lines_px, curves, fit_config, position_prior_w=item.prior)
                score = score_labelled(fit.camera, lines_px, config.tau_px, sampling)
                candidate = _Ranked(_rank_key(score, fit.cost), 0, fit.camera, score, item.label, item.prior)
                if candidate.key > best.key:
                    best = candidate
        return ReinitResult(best.camera, best.score, best.label, tried=tried)

    H = homography_from_lines(lines_px, pitch)
    if H is not None:
        reference = np.array([curves.samples_w[n].mean(axis=0) for n in lines_px])
        camera = camera_from_homography(H, width_px, height_px, reference)
        if camera is not None and consider(camera, "homography", None):
            return finish()
    if positions_w is None:
        rounds = [candidate_positions(False), [mirrored_position(p) for p in candidate_positions(False)]]
    else:
        rounds = [[tuple(p) for p in positions_w]]
    for positions in rounds:  # the mirrored positions only when the direct ones leave a class unexplained
        hypotheses = []
        for position in positions:
            for cost, camera in global_search_labelled(lines_px, position, width_px, height_px, pitch,
                                                       grid=config.grid, top_k=config.search_top_k):
                hypotheses.append((cost, camera, position))
        hypotheses.sort(key=lambda h: h[0])
        for cost, camera, position in hypotheses[: config.max_refined]:
            if consider(camera, f"search at {tuple(round(v) for v in position)}", np.asarray(position)):
                return finish()
    return finish()
