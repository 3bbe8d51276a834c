"""Fit one camera to labelled marking points: the front end's hypothesis refinement.

Used by re-initialisation and single-frame calibration to polish and *rank* many
initial hypotheses quickly (milliseconds each). It is a small robust
Levenberg-Marquardt over the tracker state ``[f, k1, pan, tilt, roll, Cx, Cy, Cz]``
with point-to-curve residuals re-associated every iteration (ICP style):

* every class element is sampled densely in 3D
  (:class:`~broadtrack_graph.geometry.template.TemplateCurves`);
* each labelled image point is associated with the closest point of its class's
  projected polyline; the residual is the signed distance along the polyline's
  normal there (point-to-tangent), so points slide freely along the marking;
* Cauchy weights per point, weak Gaussian priors on roll, k1 and (optionally) the
  focal point keep the few-class frames well posed.

No I/O. The graph's own LM (``broadtrack_graph.graph.single_frame``) is the
refinement used by the tracker; this one exists because hypothesis ranking needs
tens of fits per frame.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.state import STATE_SIZE, project_state
from broadtrack_graph.geometry.template import TemplateCurves, closest_on_polyline


@dataclass(frozen=True)
class LineFitConfig:
    """Settings of :func:`fit_camera_to_lines`."""

    line_step_m: float = 2.0  # sampling of straight markings for the projected polylines
    circle_step_m: float = 0.5  # sampling of circle arcs
    cauchy_scale_px: float = 2.0  # robust scale of the point-to-curve residual
    iterations: int = 30  # maximum LM iterations
    min_relative_decrease: float = 1e-5  # stop when the cost decreases less than this
    polish_power: float = 6.0  # > 2: finish with IRLS weights |r|^(p-2) pushing the worst points in (0 = off)
    sigma_roll_rad: float = math.radians(1.0)  # prior on roll around 0
    sigma_k1: float = 0.05  # prior on k1 around 0
    sigma_position_m: float = 8.0  # prior on the focal point around position_prior_w (when given)
    missing_class_penalty_px: float = 30.0  # residual of a point whose class is not in front of the camera
    min_focal_px_per_width: float = 0.3  # f / W lower bound (about 118 deg field of view)
    max_focal_px_per_width: float = 12.0  # f / W upper bound (about 5 deg)


@dataclass
class LineFitResult:
    """Outcome of :func:`fit_camera_to_lines`.

    camera: the fitted camera; cost: final robust cost; distances_px: class -> (M,) point-to-curve
    distances (NaN where the class is not projected); iterations: LM iterations run.
    """

    camera: Camera
    cost: float
    distances_px: dict[str, np.ndarray]
    iterations: int

    @property
    def max_distance_px(self) -> float:
        values = np.concatenate(list(self.distances_px.values())) if self.distances_px else np.zeros(1)
        return float(np.nanmax(np.where(np.isnan(values), np.inf, values))) if len(values) else 0.0


class _Problem:
    """The re-associated point-to-curve least-squares problem of one frame."""

    def __init__(self, lines_px, curves: TemplateCurves, width_px, height_px, config: LineFitConfig, position_prior_w):
        self.names = [n for n, p in lines_px.items() if n in curves.samples_w and len(p)]
        self.points = {n: np.asarray(lines_px[n], dtype=float).reshape(-1, 2) for n in self.names}
        self.curves = curves
        self.width_px, self.height_px = width_px, height_px
        self.config = config
        self.position_prior_w = None if position_prior_w is None else np.asarray(position_prior_w, float)
        self.all_samples = np.vstack([curves.samples_w[n] for n in self.names]) if self.names else np.zeros((0, 3))
        sizes = [len(curves.samples_w[n]) for n in self.names]
        self.offsets = np.concatenate([[0], np.cumsum(sizes)]).astype(int)
        self.point_count = sum(len(p) for p in self.points.values())

    def associate(self, state):
        """Distances and, per point, the 3D point of its class's curve closest in the image and the curve normal."""
        uv, _, front = project_state(state, self.all_samples, self.width_px, self.height_px, want_jacobian=False)
        anchors, normals, targets, dists, missing = [], [], [], {}, []
        for j, name in enumerate(self.names):
            s0, s1 = self.offsets[j], self.offsets[j + 1]
            poly, ok = uv[s0:s1], front[s0:s1]
            pts = self.points[name]
            valid = ok[:-1] & ok[1:]
            if not valid.any():
                dists[name] = np.full(len(pts), np.nan)
                missing.append(len(pts))
                continue
            seg, t, d = closest_on_polyline(pts, poly, valid)
            samples = self.curves.samples_w[name]
            anchors.append(samples[seg] + t[:, None] * (samples[seg + 1] - samples[seg]))
            direction = poly[seg + 1] - poly[seg]
            direction /= np.maximum(np.linalg.norm(direction, axis=1, keepdims=True), 1e-12)
            normals.append(np.stack([-direction[:, 1], direction[:, 0]], axis=1))
            targets.append(pts)
            dists[name] = d
        if anchors:
            return np.vstack(anchors), np.vstack(normals), np.vstack(targets), dists, sum(missing)
        return np.zeros((0, 3)), np.zeros((0, 2)), np.zeros((0, 2)), dists, sum(missing)

    def robust_cost(self, dists: dict, missing_count: int, state) -> float:
        s = self.config.cauchy_scale_px
        values = np.concatenate([d[~np.isnan(d)] for d in dists.values()]) if dists else np.zeros(0)
        cost = float(np.sum(np.log1p((values / s) ** 2)))
        cost += missing_count * math.log1p((self.config.missing_class_penalty_px / s) ** 2)
        return cost + 0.5 * float(np.sum(self.prior_residuals(state) ** 2))

    def prior_residuals(self, state) -> np.ndarray:
        c = self.config
        res = [state[4] / c.sigma_roll_rad, state[1] / c.sigma_k1]
        if self.position_prior_w is not None:
            res.extend((state[5:8] - self.position_prior_w) / c.sigma_position_m)
        return np.asarray(res)

    def prior_jacobian(self) -> np.ndarray:
        c = self.config
        rows = [np.eye(STATE_SIZE)[4] / c.sigma_roll_rad, np.eye(STATE_SIZE)[1] / c.sigma_k1]
        if self.position_prior_w is not None:
            rows.extend(np.eye(STATE_SIZE)[5:8] / c.sigma_position_m)
        return np.asarray(rows)


def _residuals_and_jacobian(problem: _Problem, state, anchors, normals, targets):
    """Point-to-tangent residuals (M,) and their analytic Jacobian (M, 8) (broadtrack_graph.geometry.state)."""
    uv, J_uv, _ = project_state(state, anchors, problem.width_px, problem.height_px)
    r = np.einsum("ij,ij->i", normals, uv - targets)
    return r, np.einsum("ij,ijk->ik", normals, J_uv)


def fit_camera_to_lines(
    initial: Camera,
    lines_px: dict[str, np.ndarray],
    curves: TemplateCurves | None = None,
    config: LineFitConfig | None = None,
    position_prior_w=None,
    fixed: tuple[int, ...] = (),
) -> LineFitResult:
    """Robust LM fit of a camera to per-class image points (see module docstring).

    Args:
        initial: starting camera (its width_px / height_px are those of lines_px).
        lines_px: class name -> (M, 2) pixels on that marking.
        curves: template samples (built once and reused).
        config: settings.
        position_prior_w: (3,) metres, weak prior centre for the focal point, or None.
        fixed: state indices held at their initial value (e.g. (1,) to keep k1).

    Returns:
        LineFitResult with the fitted camera.
    """
    config = config or LineFitConfig()
    curves = curves or TemplateCurves(line_step_m=config.line_step_m, circle_step_m=config.circle_step_m)
    W, H = initial.width_px, initial.height_px
    problem = _Problem(lines_px, curves, W, H, config, position_prior_w)
    state = initial.to_vector()
    anchors, normals, targets, dists, missing = problem.associate(state)
    cost = problem.robust_cost(dists, missing, state)
    free = np.array([i not in fixed for i in range(STATE_SIZE)])
    lam = 1e-3
    f_lo, f_hi = config.min_focal_px_per_width * W, config.max_focal_px_per_width * W
    iteration = 0

    def evaluate(candidate):
        associated = problem.associate(candidate)
        return problem.robust_cost(associated[3], associated[4], candidate), associated

    for iteration in range(1, config.iterations + 1):
        if len(anchors) == 0:
            break
        r, J = _residuals_and_jacobian(problem, state, anchors, normals, targets)
        s = config.cauchy_scale_px
        w = 1.0 / (1.0 + (r / s) ** 2)
        Jp, rp = problem.prior_jacobian(), problem.prior_residuals(state)
        A = (J * w[:, None]).T @ J + Jp.T @ Jp
        g = (J * w[:, None]).T @ r + Jp.T @ rp
        A, g = A[np.ix_(free, free)], g[free]

        improved, candidate, c_cost, associated, lam = _damped_step(state, free, A, g, lam, 8, (f_lo, f_hi), evaluate,
                                                                    cost, 1e-7)
        if improved:
            relative = (cost - c_cost) / max(cost, 1e-12)
            state, cost = candidate, c_cost
            anchors, normals, targets, dists, missing = associated
        if not improved or relative < config.min_relative_decrease:
            break
    if config.polish_power > 2 and len(anchors):
        state, dists = _polish(problem, state, free, config, (f_lo, f_hi))
    camera = Camera.from_vector(state, W, H)
    return LineFitResult(camera, cost, dists, iteration)


def _damped_step(state, free, A, g, lam: float, tries: int, focal_bounds, evaluate, current: float,
                 lam_min: float):
    """One Levenberg-Marquardt step on the free parameters: raise the damping until the objective decreases.

    Args:
        A, g: normal matrix and gradient restricted to the free parameters.
        evaluate: candidate state -> (objective, payload); current: the objective at ``state``.

    Returns:
        (accepted, candidate state, its objective, its payload, new damping).
    """
    for _ in range(tries):
        try:
            delta = np.linalg.solve(A + lam * np.diag(np.diag(A) + 1e-9), -g)
        except np.linalg.LinAlgError:
            lam *= 10
            continue
        candidate = state.copy()
        candidate[free] += delta
        candidate[0] = min(max(candidate[0], focal_bounds[0]), focal_bounds[1])
        value, payload = evaluate(candidate)
        if value < current:
            return True, candidate, value, payload, max(lam / 10, lam_min)
        lam *= 10
    return False, state, current, None, lam


def _polish(problem: _Problem, state, free, config: LineFitConfig, focal_bounds, iterations: int = 12, cap_px: float = 12.0):
    """Push the worst points in: IRLS on sum min(|d|, cap)^p (p = config.polish_power), distances re-associated."""
    p = config.polish_power

    def objective(dists):
        values = np.concatenate([d for d in dists.values()]) if dists else np.zeros(0)
        values = np.where(np.isnan(values), cap_px, np.minimum(values, cap_px))
        return float(np.sum(values**p))

    def evaluate(candidate):
        associated = problem.associate(candidate)
        return objective(associated[3]), associated

    anchors, normals, targets, dists, _ = problem.associate(state)
    best = objective(dists)
    lam = 1e-2
    for _ in range(iterations):
        if len(anchors) == 0:
            break
        r, J = _residuals_and_jacobian(problem, state, anchors, normals, targets)
        a = np.abs(r)
        w = np.where(a < cap_px, np.maximum(a, 0.3) ** (p - 2), 0.0)
        w /= max(w.max(), 1e-12)
        Jp, rp = problem.prior_jacobian(), problem.prior_residuals(state)
        scale = 1e-3
        A = (J * w[:, None]).T @ J + scale * Jp.T @ Jp
        g = (J * w[:, None]).T @ r + scale * Jp.T @ rp
        A, g = A[np.ix_(free, free)], g[free]

        accepted, candidate, value, associated, lam = _damped_step(state, free, A, g, lam, 5, focal_bounds, evaluate,
                                                                   best, 1e-6)
        if accepted:
            best, state = value, candidate
            anchors, normals, targets, dists = associated[:4]
        if not accepted:
            break
    return state, dists
