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
from broadtrack_graph.geometry.template import TemplateCurves, to_segments
from broadtrack_graph.reinit.linefit_pairs import FitLayout, NearestSegments, PointSegmentPairs


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
    # Each point is matched first among its class's segments within this share of the width (the same match, found
    # quicker; with a point farther from every one, all are measured: linefit_pairs). Speed only: no fit changes.
    association_reach_per_width: float = 0.025


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
        self.width_px, self.height_px = width_px, height_px
        self.config = config
        self.position_prior_w = None if position_prior_w is None else np.asarray(position_prior_w, float)
        self.all_samples = np.vstack([curves.samples_w[n] for n in self.names]) if self.names else np.zeros((0, 3))
        sizes = [len(curves.samples_w[n]) for n in self.names]
        self.layout = FitLayout([len(self.points[n]) for n in self.names], sizes)
        self.all_points = np.vstack([self.points[n] for n in self.names]) if self.names else np.zeros((0, 2))
        self._nearest = NearestSegments(self.all_points, self.layout,
                                        max(config.association_reach_per_width * width_px, 2.0))
        self._pairs = None  # every pair (PointSegmentPairs), made when a point is first out of reach
        c = config
        rows = [np.eye(STATE_SIZE)[4] / c.sigma_roll_rad, np.eye(STATE_SIZE)[1] / c.sigma_k1]
        if self.position_prior_w is not None:
            rows.extend(np.eye(STATE_SIZE)[5:8] / c.sigma_position_m)
        self._prior_jacobian = np.asarray(rows)
        self.prior_normal = self._prior_jacobian.T @ self._prior_jacobian  # (8, 8) Jp^T Jp, a constant of the fit

    def associate(self, state) -> "_Association":
        """Each point's nearest segment of its class's projected polyline (the distances now; the residuals' geometry
        when asked, :meth:`_Association.geometry`)."""
        uv, _, front = project_state(state, self.all_samples, self.width_px, self.height_px, want_jacobian=False)
        layout = self.layout
        usable = front[:-1] & front[1:] & layout.joins_next  # segments of a class with both ends in front
        class_seen = np.logical_or.reduceat(usable, layout.class_segment_start) if len(usable) else usable
        if class_seen.all():
            with np.errstate(invalid="ignore", over="ignore"):
                near = self._nearest.within_reach(uv, usable)
            if near is not None:
                segment, t, distances = near
                return _Association(self, uv, segment, t, slice(None), distances, 0)
        # Every point against every segment of its class at once (one flat array of pairs, in segment then point
        # order): the projection of the point on the segment, clipped to it, and the squared distance. The
        # segments' numbers are repeated for the pairs in one call: rows start x, start y, dx, dy, squared length.
        if self._pairs is None:
            self._pairs = PointSegmentPairs(layout)
            self._pair_x, self._pair_y = (self.all_points[:, k].take(self._pairs.point) for k in (0, 1))  # (pairs,)
            self._blocked = np.empty(len(usable), bool)  # (segments,) scratch
        pairs = self._pairs
        s = pairs.segment
        with np.errstate(invalid="ignore", over="ignore"):
            seg_d = uv[1:] - uv[:-1]
            table = np.empty((5, len(seg_d)))
            table[0:2] = uv[:-1].T
            table[2:4] = seg_d.T
            table[4] = np.maximum(np.einsum("ij,ij->i", seg_d, seg_d), 1e-12)
            t, dist2 = to_segments(self._pair_x, self._pair_y, *table.repeat(pairs.segment_pairs, axis=1))
        np.logical_not(usable, out=self._blocked)
        np.copyto(dist2, np.inf, where=self._blocked.repeat(pairs.segment_pairs))
        nearest = pairs.first_minimum(dist2)
        distances = np.sqrt(dist2.take(nearest))
        if class_seen.all():
            return _Association(self, uv, s.take(nearest), t.take(nearest), slice(None), distances, 0)
        missing_points = np.repeat(~class_seen, layout.class_points)
        distances[missing_points] = np.nan
        keep = ~missing_points
        return _Association(self, uv, s[nearest][keep], t[nearest][keep], keep, distances,
                            int(layout.class_points[~class_seen].sum()))

    def robust_cost(self, association: "_Association", state) -> float:
        s = self.config.cauchy_scale_px
        values = association.distances[~np.isnan(association.distances)]
        cost = float(np.add.reduce(np.log1p((values / s) ** 2)))  # np.sum's own reduction, without its wrapper
        cost += association.missing * math.log1p((self.config.missing_class_penalty_px / s) ** 2)
        return cost + 0.5 * float(np.add.reduce(self.prior_residuals(state) ** 2))

    def prior_residuals(self, state) -> np.ndarray:
        """(2,) roll and k1 over their sigmas, then (3,) the focal point's offset from its prior over its sigma (when
        given)."""
        c = self.config
        res = np.empty(len(self._prior_jacobian))
        res[0], res[1] = state[4] / c.sigma_roll_rad, state[1] / c.sigma_k1
        if self.position_prior_w is not None:
            res[2:] = (state[5:8] - self.position_prior_w) / c.sigma_position_m
        return res

    def prior_jacobian(self) -> np.ndarray:
        """(2 or 5, 8) the Jacobian of :meth:`prior_residuals` (a constant of the problem)."""
        return self._prior_jacobian


class _Association:
    """One association of a fit's points (:meth:`_Problem.associate`).

    distances: (points,) pixels to the nearest segment of each point's class, NaN for the points of a class not in
    front of the camera (class order); missing: how many points those are. The geometry the residuals need is made
    only when asked (an LM step that is not taken never asks).
    """

    def __init__(self, problem: _Problem, uv, segment, t, keep, distances, missing: int) -> None:
        self._problem, self._uv, self._segment, self._t, self._keep = problem, uv, segment, t, keep
        self.distances, self.missing = distances, missing
        self._geometry = None

    @property
    def dists(self) -> dict[str, np.ndarray]:
        """Class name -> (M,) distances in pixels (NaN for a class not in front)."""
        return dict(zip(self._problem.names, np.split(self.distances, self._problem.layout.point_offsets[1:-1])))

    def geometry(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(anchors (P, 3) metres, normals (P, 2), targets (P, 2) pixels) of the P points of the classes in front:
        the point of the class's curve nearest each point in the image, the curve's image normal there, the point."""
        if self._geometry is None:
            samples, uv, seg, t = self._problem.all_samples, self._uv, self._segment, self._t
            a = samples[seg]
            anchors = a + t[:, None] * (samples[seg + 1] - a)
            direction = uv[seg + 1] - uv[seg]
            length = np.sqrt(np.add.reduce(direction * direction, axis=1, keepdims=True))  # np.linalg.norm's sum
            direction /= np.maximum(length, 1e-12)
            normals = np.empty_like(direction)
            normals[:, 0], normals[:, 1] = -direction[:, 1], direction[:, 0]
            self._geometry = (anchors, normals, self._problem.all_points[self._keep])
        return self._geometry


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
    association = problem.associate(state)
    cost = problem.robust_cost(association, state)
    free = np.array([i not in fixed for i in range(STATE_SIZE)])
    free_rows, free_columns = np.ix_(free, free)
    lam = 1e-3
    f_lo, f_hi = config.min_focal_px_per_width * W, config.max_focal_px_per_width * W
    iteration = 0

    def evaluate(candidate):
        associated = problem.associate(candidate)
        return problem.robust_cost(associated, candidate), associated

    for iteration in range(1, config.iterations + 1):
        anchors, normals, targets = association.geometry()
        if len(anchors) == 0:
            break
        r, J = _residuals_and_jacobian(problem, state, anchors, normals, targets)
        s = config.cauchy_scale_px
        w = 1.0 / (1.0 + (r / s) ** 2)
        Jw = J * w[:, None]
        A = Jw.T @ J + problem.prior_normal
        g = Jw.T @ r + problem.prior_jacobian().T @ problem.prior_residuals(state)
        A, g = A[free_rows, free_columns], g[free]

        improved, candidate, c_cost, associated, lam = _damped_step(state, free, A, g, lam, 8, (f_lo, f_hi), evaluate,
                                                                    cost, 1e-7)
        if improved:
            relative = (cost - c_cost) / max(cost, 1e-12)
            state, cost, association = candidate, c_cost, associated
        if not improved or relative < config.min_relative_decrease:
            break
    dists = association.dists
    if config.polish_power > 2 and len(association.geometry()[0]):
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


def _polish(problem: _Problem, state, free, config: LineFitConfig, focal_bounds, iterations: int = 12,
            cap_px: float = 12.0):
    """Push the worst points in: IRLS on sum min(|d|, cap)^p (p = config.polish_power), distances re-associated."""
    p = config.polish_power

    def objective(association):
        values = association.distances
        values = np.where(np.isnan(values), cap_px, np.minimum(values, cap_px))
        return float(np.sum(values**p))

    def evaluate(candidate):
        associated = problem.associate(candidate)
        return objective(associated), associated

    association = problem.associate(state)
    best = objective(association)
    lam = 1e-2
    scaled_prior_transposed = 1e-3 * problem.prior_jacobian().T  # the priors weigh 1e-3 here
    prior_normal = scaled_prior_transposed @ problem.prior_jacobian()
    free_rows, free_columns = np.ix_(free, free)
    for _ in range(iterations):
        anchors, normals, targets = association.geometry()
        if len(anchors) == 0:
            break
        r, J = _residuals_and_jacobian(problem, state, anchors, normals, targets)
        a = np.abs(r)
        w = np.where(a < cap_px, np.maximum(a, 0.3) ** (p - 2), 0.0)
        w /= max(w.max(), 1e-12)
        Jw = J * w[:, None]
        A = Jw.T @ J + prior_normal
        g = Jw.T @ r + scaled_prior_transposed @ problem.prior_residuals(state)
        A, g = A[free_rows, free_columns], g[free]

        accepted, candidate, value, associated, lam = _damped_step(state, free, A, g, lam, 5, focal_bounds, evaluate,
                                                                   best, 1e-6)
        if accepted:
            best, state, association = value, candidate, associated
        if not accepted:
            break
    return state, association.dists
