"""Re-initialisation: a camera (and a score) from one frame's detections, no history.

Three ways in, all returning ``(camera, score)`` or ``(None, reason)``:

* :func:`reinit_from_keypoints`: labelled keypoints; the two-point method of DESIGN.md
  (focal point at the tripod T, roll 0: f from the angle between the two rays, then
  pan/tilt by rotation alignment) inside RANSAC over pairs, then refinement.
* :func:`reinit_from_lines`: per-class line points (a learned detector, or annotations):
  a homography from >= 4 straight-line correspondences when there are enough,
  and a global pan/tilt/f search for each candidate tripod position, each
  hypothesis refined and the best-scoring kept.
* :func:`~broadtrack_graph.reinit.mask.reinit_from_mask` (module
  ``reinit_mask``): the weight-free case, no labels: camera hypotheses from the
  structure of the marking map at each candidate tripod (two straight markings on two pitch
  lines, a pitch circle on an ellipse; scale-free, so tight zooms are found as well as wide
  views), each scored against the map, the best fitted after naming the map's points by the
  projected template.

When no tripod is known, :data:`DEFAULT_TRIPOD_POSITIONS_W` are all tried.
Conventions: world z down, pan 0 looks towards -y (DESIGN.md). No I/O.
"""

from __future__ import annotations

import itertools
import logging
import math
from dataclasses import dataclass, replace

import numpy as np

from broadtrack_graph.geometry.camera import Camera, angles_from_rotation
from broadtrack_graph.geometry.template import (
    TemplateCurves, TemplateSampling, distances_to_polyline, project_template_polylines,
)
from broadtrack_graph.reinit.linefit import LineFitConfig, fit_camera_to_lines
from broadtrack_graph.geometry.state import project_state
from broadtrack_graph.geometry.pitch import Arc, PitchTemplate, Segment

log = logging.getLogger(__name__)

DEFAULT_TRIPOD_POSITIONS_W: dict[str, tuple[float, float, float]] = {
    "main": (0.0, 55.0, -12.0),
    "16m left": (-36.0, 55.0, -12.0),
    "16m right": (36.0, 55.0, -12.0),
    "high behind goal": (-65.0, 0.0, -15.0),
}
"""Focal-point guesses for the common broadcast cameras (metres, pitch frame, z down)."""


def mirrored_position(position_w) -> tuple[float, float, float]:
    """The position reflected through the pitch centre (x, y -> -x, -y)."""
    x, y, z = position_w
    return (-x, -y, z)


def candidate_positions(include_mirrored: bool = True) -> list[tuple[float, float, float]]:
    """The default tripod positions, plus their reflections through the centre (labels may be mirrored)."""
    positions = list(DEFAULT_TRIPOD_POSITIONS_W.values())
    if include_mirrored:
        positions += [mirrored_position(p) for p in DEFAULT_TRIPOD_POSITIONS_W.values()]
    return positions


def facing_pan_rad(position_w) -> float:
    """Pan (radians) that points a camera at position_w towards the centre spot (pan 0 looks to -y)."""
    x, y, _ = position_w
    return math.atan2(-x, y) if (x or y) else 0.0


# --------------------------------------------------------------------------- two-point method


def focal_from_ray_angle(uv_px: np.ndarray, angle_rad: float, width_px: int, height_px: int) -> float | None:
    """Focal length (pixels) at which the rays of two pixels make a given angle.

    The angle between the rays ``(u - cx, v - cy, f)`` decreases monotonically with f, so it is
    solved by bisection on log f. None when the angle cannot be reached.
    """
    d = np.asarray(uv_px, dtype=float) - [width_px / 2.0, height_px / 2.0]

    def angle(f: float) -> float:
        a = np.array([d[0, 0], d[0, 1], f])
        b = np.array([d[1, 0], d[1, 1], f])
        return math.acos(float(np.clip(a @ b / (np.linalg.norm(a) * np.linalg.norm(b)), -1, 1)))

    lo, hi = 0.05 * width_px, 50.0 * width_px
    if not (angle(hi) <= angle_rad <= angle(lo)):
        return None
    for _ in range(60):
        mid = math.sqrt(lo * hi)
        if angle(mid) > angle_rad:
            lo = mid
        else:
            hi = mid
    return math.sqrt(lo * hi)


def camera_from_two_points(uv_px, points_w, position_w, width_px: int, height_px: int) -> Camera | None:
    """The two-point method: focal point fixed at position_w, roll 0, k1 0.

    Args:
        uv_px: (2, 2) pixels of two pitch points; points_w: (2, 3) their positions (metres).
        position_w: (3,) focal point (the tripod T).

    Returns:
        The camera, or None when the pair is degenerate or the angle cannot be matched.
    """
    uv_px = np.asarray(uv_px, dtype=float).reshape(2, 2)
    rays_w = np.asarray(points_w, dtype=float).reshape(2, 3) - np.asarray(position_w, dtype=float)
    norms = np.linalg.norm(rays_w, axis=1)
    if np.any(norms < 1e-6) or np.linalg.norm(uv_px[0] - uv_px[1]) < 2.0:
        return None
    rays_w /= norms[:, None]
    angle = math.acos(float(np.clip(rays_w[0] @ rays_w[1], -1, 1)))
    focal = focal_from_ray_angle(uv_px, angle, width_px, height_px)
    if focal is None:
        return None
    rays_c = np.column_stack([uv_px - [width_px / 2.0, height_px / 2.0], np.full(2, focal)])
    rays_c /= np.linalg.norm(rays_c, axis=1, keepdims=True)
    # Rotation aligning world rays onto camera rays (Kabsch with the two rays and their cross product).
    a = np.vstack([rays_w, np.cross(rays_w[0], rays_w[1])])
    b = np.vstack([rays_c, np.cross(rays_c[0], rays_c[1])])
    u, _, vt = np.linalg.svd(b.T @ a)
    R_cw = u @ np.diag([1, 1, np.sign(np.linalg.det(u @ vt))]) @ vt
    pan, tilt, _ = angles_from_rotation(R_cw)
    camera = Camera(focal, 0.0, pan, tilt, 0.0, np.asarray(position_w, float), width_px, height_px)
    # A few fixed-point steps on pan/tilt with roll held at 0: align the mean ray.
    for _ in range(3):
        uv, front = camera.project(np.asarray(points_w, dtype=float).reshape(2, 3))
        if not front.all():
            return None
        shift = (uv_px - uv).mean(axis=0) / focal
        camera = camera.replace(pan_rad=camera.pan_rad + shift[0] / max(math.sin(camera.tilt_rad), 0.2),
                                tilt_rad=camera.tilt_rad - shift[1])
    return camera


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
        world = np.cross([*element.start_w[:2], 1.0], [*element.end_w[:2], 1.0])
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
        M = np.column_stack([r1, r2, np.cross(r1, r2)])
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


# --------------------------------------------------------------------------- scoring


@dataclass
class LabelledScore:
    """Agreement of a camera with per-class detections at threshold tau (the JaC of the SoccerNet metric).

    jaccard: TP / (TP + FP + FN) over classes; tp/fp/fn: class counts; inlier_share: share of points within tau.
    """

    jaccard: float
    tp: int
    fp: int
    fn: int
    inlier_share: float
    mean_distance_px: float


def score_labelled(camera: Camera, lines_px: dict[str, np.ndarray], tau_px: float = 5.0,
                   sampling: TemplateSampling | None = None) -> LabelledScore:
    """Per-class agreement: a class detected and projected is TP when all its points are within tau_px.

    Classes projected but not detected count as FP, detected but not projected as FN.
    """
    polylines = project_template_polylines(camera, camera.width_px, camera.height_px, sampling)
    tp = fp = fn = 0
    inliers = total = 0
    distance_sum = 0.0
    for name, points in lines_px.items():
        if not len(points):
            continue
        poly = polylines.get(name)
        if poly is None or len(poly) == 0:
            fn += 1
            total += len(points)
            continue
        if len(poly) == 1:
            distances = np.linalg.norm(points - poly[0], axis=1)
        else:
            distances = distances_to_polyline(np.asarray(points, float), poly)
        inliers += int(np.sum(distances < tau_px))
        total += len(points)
        distance_sum += float(np.sum(np.minimum(distances, 100.0)))
        if distances.max() < tau_px:
            tp += 1
        else:
            fp += 1
    fp += sum(1 for name in polylines if name not in lines_px)
    jac = tp / max(tp + fp + fn, 1)
    return LabelledScore(jac, tp, fp, fn, inliers / max(total, 1), distance_sum / max(total, 1))


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


@dataclass
class ReinitResult:
    """Outcome of a re-initialisation: camera (None when nothing fits), score, which hypothesis won, reason."""

    camera: Camera | None
    score: LabelledScore | None
    hypothesis: str
    reason: str = ""
    tried: int = 0


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
    ranked: list[tuple] = []
    tried = 0
    coarse_config = replace(fit_config, polish_power=0.0, iterations=config.coarse_iterations)

    def consider(initial: Camera, label: str, prior):
        nonlocal tried
        tried += 1
        fit = fit_camera_to_lines(initial, lines_px, curves, coarse_config, position_prior_w=prior)
        score = score_labelled(fit.camera, lines_px, config.tau_px, sampling)
        ranked.append((_rank_key(score, fit.cost), tried, fit.camera, score, label, prior))
        return fit.max_distance_px < config.good_enough_max_px or score.inlier_share >= config.good_enough_inlier_share

    def finish() -> ReinitResult:
        if not ranked:
            return ReinitResult(None, None, "", "no hypothesis could be formed", tried)
        ranked.sort(key=lambda item: item[:2], reverse=True)
        best = ranked[0]
        if fit_config.polish_power > 2:
            for _, _, camera, _, label, prior in ranked[: config.polished]:
                fit = fit_camera_to_lines(camera, lines_px, curves, fit_config, position_prior_w=prior)
                score = score_labelled(fit.camera, lines_px, config.tau_px, sampling)
                candidate = (_rank_key(score, fit.cost), 0, fit.camera, score, label, prior)
                if candidate[0] > best[0]:
                    best = candidate
        return ReinitResult(best[2], best[3], best[4], tried=tried)

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


# --------------------------------------------------------------------------- re-initialisation from keypoints


def reinit_from_keypoints(
    uv_px: np.ndarray,
    points_w: np.ndarray,
    width_px: int,
    height_px: int,
    positions_w=None,
    inlier_px: float = 10.0,
    max_pairs: int = 60,
    seed: int = 0,
) -> ReinitResult:
    """Camera from labelled keypoints: two-point method in RANSAC over pairs, then refinement.

    For each candidate focal point (default: :data:`DEFAULT_TRIPOD_POSITIONS_W`), pairs of
    keypoints give cameras (:func:`camera_from_two_points`); the one with most keypoints
    within ``inlier_px`` wins, and f, pan, tilt, roll and the focal point are then refined
    on its inliers (Cauchy-weighted Gauss-Newton on the reprojection error, weak priors).

    Args:
        uv_px: (N, 2) pixels; points_w: (N, 3) metres. N >= 2.

    Returns:
        ReinitResult (score.inlier_share = share of keypoints within inlier_px; jaccard unused = 0).
    """
    uv_px = np.asarray(uv_px, float).reshape(-1, 2)
    points_w = np.asarray(points_w, float).reshape(-1, 3)
    if len(uv_px) < 2:
        return ReinitResult(None, None, "", "fewer than 2 keypoints")
    positions = list(DEFAULT_TRIPOD_POSITIONS_W.values()) if positions_w is None else [tuple(p) for p in positions_w]
    rng = np.random.default_rng(seed)
    pairs = list(itertools.combinations(range(len(uv_px)), 2))
    if len(pairs) > max_pairs:
        pairs = [pairs[i] for i in rng.choice(len(pairs), max_pairs, replace=False)]
    best = None
    for position in positions:
        for i, j in pairs:
            camera = camera_from_two_points(uv_px[[i, j]], points_w[[i, j]], position, width_px, height_px)
            if camera is None:
                continue
            uv, front = camera.project(points_w)
            err = np.where(front, np.linalg.norm(uv - uv_px, axis=1), np.inf)
            inliers = err < inlier_px
            key = (int(inliers.sum()), -float(np.sum(np.minimum(err, inlier_px))))
            if best is None or key > best[0]:
                best = (key, camera, inliers, position)
    if best is None:
        return ReinitResult(None, None, "", "no keypoint pair gave a camera", len(pairs))
    _, camera, inliers, position = best
    camera = _refine_on_keypoints(camera, uv_px[inliers], points_w[inliers], np.asarray(position, float))
    uv, front = camera.project(points_w)
    err = np.where(front, np.linalg.norm(uv - uv_px, axis=1), np.inf)
    share = float(np.mean(err < inlier_px))
    score = LabelledScore(0.0, 0, 0, 0, share, float(np.mean(np.minimum(err, 100.0))))
    return ReinitResult(camera, score, f"two-point at {tuple(round(v) for v in position)}", tried=len(pairs))


def _refine_on_keypoints(camera: Camera, uv_px, points_w, position_w, iterations: int = 15,
                         cauchy_px: float = 5.0, sigma_position_m: float = 5.0) -> Camera:
    """Gauss-Newton on keypoint reprojection (free: f, pan, tilt, roll, C; k1 held), Cauchy weights, priors."""
    if len(uv_px) < 3:
        return camera
    W, H = camera.width_px, camera.height_px
    state = camera.to_vector()
    free = np.array([0, 2, 3, 4, 5, 6, 7])
    prior_sig = np.array([np.inf, np.inf, np.inf, np.inf, math.radians(1.0), sigma_position_m, sigma_position_m, sigma_position_m])
    for _ in range(iterations):
        uv, J_uv, front = project_state(state, points_w, W, H)
        if not front.all():
            break
        r = (uv - uv_px).ravel()
        J = J_uv.reshape(-1, 8)
        w = 1.0 / (1.0 + (r / cauchy_px) ** 2)
        prior_r = np.zeros(8)
        prior_r[4] = state[4]
        prior_r[5:8] = state[5:8] - position_w
        pw = np.where(np.isfinite(prior_sig), 1.0 / prior_sig**2, 0.0)
        A = (J * w[:, None]).T @ J + np.diag(pw)
        g = (J * w[:, None]).T @ r + pw * prior_r
        A, g = A[np.ix_(free, free)], g[free]
        try:
            delta = np.linalg.solve(A + 1e-6 * np.diag(np.diag(A)), -g)
        except np.linalg.LinAlgError:
            break
        state[free] += delta
        if np.max(np.abs(delta[1:4])) < 1e-8:
            break
    try:
        return Camera.from_vector(state, W, H)
    except ValueError:
        return camera
