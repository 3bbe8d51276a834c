"""Tripod fit from an existing track: T and delta such that every optical axis passes
at distance delta from T (the paper's "track without the tripod term, then fit").

Fit of the full tripod model ``C = T - delta r2 + lambda r3``: each optical axis passes
through ``T - delta r2``, i.e. ``P_i (T - delta r2_i) = P_i C_i`` with
``P_i = I - r3 r3^T``: linear in (T, delta), solved by iteratively reweighted least
squares with a graduated Cauchy loss (robust to outlier frames). The distance-only
cost ``delta - |O*_i - T|`` of the paper has a flat valley that outliers drag along,
so it is only reported (``info["residuals_m"]``). No assumption on where the camera stands.

Observability: T and delta are separated only by the change of the camera's up vector
between frames. A camera whose tilt barely changes (a main camera tilts by 1-3 deg)
leaves the combination "T moved along the up vector, delta changed by the same amount"
nearly free; ``info["condition"]`` grows, and the horizontal position of T stays well
determined while its height and delta do not.
"""

from __future__ import annotations

import logging
import math

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.tripod import Tripod

logger = logging.getLogger(__name__)

MIN_FRAMES = 3


def _axis_residuals(params: np.ndarray, centres: np.ndarray, axes: np.ndarray) -> np.ndarray:
    T, delta = params[:3], params[3]
    d = centres - T
    w = d - np.sum(d * axes, axis=1, keepdims=True) * axes
    return delta - np.linalg.norm(w, axis=1)


def fit_tripod(
    cameras: list[Camera | None],
    scale_m: float = 0.05,
    outlier_threshold_m: float = 0.3,
    delta_prior_m: float | None = None,
    delta_prior_sigma_m: float = 0.1,
) -> tuple[Tripod | None, dict]:
    """Fit the tripod (T_w, delta_m) to cameras of one tripod.

    Args:
        cameras: estimated cameras (None entries are skipped).
        scale_m: Cauchy scale of the axis-distance residuals, metres.
        outlier_threshold_m: frames whose |residual| exceeds this are reported as outliers.
        delta_prior_m: optional Gaussian prior on delta (mean, metres) with delta_prior_sigma_m.
            Needed when the tilt barely changes (see the module note): without it the height
            of T and delta drift together along a nearly free direction.

    Returns:
        tripod: the fitted Tripod, or None when fewer than 3 cameras or the axes are degenerate
            (all parallel); info["reason"] says why.
        info: "residuals_m" (N,) delta - |O* - T| per used camera, "axis_point_miss_m" (N,)
            distance of each optical axis from T - delta r2, "inliers" (N,) bool (miss below
            outlier_threshold_m),
            "inlier_ratio", "rms_inlier_m", "used_frames" (indices into cameras),
            "condition" (of the normal equations; large = poorly constrained), "std_T_m" (3,)
            and "std_delta_m" (first-order standard deviations assuming scale_m per frame),
            "reason".
    """
    used = [i for i, c in enumerate(cameras) if c is not None]
    info: dict = {"used_frames": used, "reason": None}
    if len(used) < MIN_FRAMES:
        info["reason"] = f"only {len(used)} cameras, need {MIN_FRAMES}"
        return None, info
    centres = np.array([cameras[i].position_m for i in used])
    rotations = np.array([cameras[i].R_cw for i in used])
    axes = rotations[:, 2]  # r3: optical axes
    ups = rotations[:, 1]  # r2 (minus the camera's up vector)
    # Robust linear start from the full model C = T - delta r2 + lambda r3: the optical axis
    # passes through T - delta r2, i.e. P_i (T - delta r2_i) = P_i C_i with P_i = I - r3 r3^T
    # (P_i r2_i = r2_i). Linear in (T, delta); iteratively reweighted against outlier frames.
    projectors = np.eye(3)[None] - axes[:, :, None] * axes[:, None, :]
    A_rows = np.concatenate([projectors, -ups[:, :, None]], axis=2)  # (N, 3, 4)
    b_rows = np.einsum("nij,nj->ni", projectors, centres)  # (N, 3)
    weights = np.ones(len(used))
    params = np.zeros(4)
    condition = float("inf")
    for iteration in range(30):
        AtA = np.einsum("n,nki,nkj->ij", weights, A_rows, A_rows) / scale_m**2
        Atb = np.einsum("n,nki,nk->i", weights, A_rows, b_rows) / scale_m**2
        if delta_prior_m is not None:
            AtA[3, 3] += 1.0 / delta_prior_sigma_m**2
            Atb[3] += delta_prior_m / delta_prior_sigma_m**2
        condition = float(np.linalg.cond(AtA))
        if not np.isfinite(condition) or condition > 1e14:
            info["reason"] = "optical axes are (nearly) parallel: the tripod point is not determined"
            info["condition"] = condition
            return None, info
        new_params = np.linalg.solve(AtA, Atb)
        miss = np.linalg.norm(np.einsum("nij,j->ni", A_rows, new_params) - b_rows, axis=1)
        # Graduated Cauchy scale: from the spread of the misses down to scale_m.
        spread = max(float(np.median(miss)) * 3.0 * 0.5 ** iteration, scale_m)
        weights = 1.0 / (1.0 + (miss / spread) ** 2)
        converged = np.max(np.abs(new_params - params)) < 1e-7
        params = new_params
        if converged and spread == scale_m:
            break
    info["axis_point_miss_m"] = miss
    covariance = np.linalg.inv(AtA)
    info["std_T_m"] = np.sqrt(np.diag(covariance)[:3]).tolist()
    info["std_delta_m"] = float(np.sqrt(covariance[3, 3]))
    residuals = _axis_residuals(params, centres, axes)
    inliers = miss < outlier_threshold_m
    info.update(
        residuals_m=residuals,
        inliers=inliers,
        inlier_ratio=float(inliers.mean()),
        rms_inlier_m=float(np.sqrt(np.mean(miss[inliers] ** 2))) if inliers.any() else float("nan"),
        condition=condition,
    )
    return Tripod.from_vector(params), info


def provisional_tripod(cameras: list[Camera], delta_m: float = 0.2, lambda_m: float = 0.2,
                       lambda_sigma_m: float = 0.0) -> Tripod | None:
    """A tripod from a few cameras whose pan range is too small for :func:`fit_tripod`.

    Inverts the tripod model ``C = T - delta r2 + lambda r3`` with typical delta and lambda:
    ``T_i = C_i + delta r2_i - lambda r3_i`` per camera, and T is their per-axis median. Its ``sigma_m`` is how
    uncertain that median is: the T_i scatter about it by their RMS distance, of which the model itself allows
    ``lambda_sigma_m`` (the focal point's place on the optical axis moves with the zoom about the typical lambda); the
    scatter beyond that over the square root of the cameras' count. Opening frames that disagree where the camera
    stands (a trade-off of distance, height and tilt the markings in view leave open) make a loose tripod.
    Online, it holds the focal point in place from the first confident frames (without a
    tripod, biased detections at tight zoom can walk it metres in a hundred frames) until
    there are enough frames to fit.

    Args:
        cameras: trusted cameras of one tripod (None entries are skipped).
        delta_m, lambda_m: the assumed offsets (metres).
        lambda_sigma_m: how far lambda strays from lambda_m (metres; the scatter of the T_i it explains).

    Returns:
        Tripod(T, delta_m, sigma_m), or None without a camera.
    """
    used = [c for c in cameras if c is not None]
    if not used:
        return None
    rotations = np.array([c.R_cw for c in used])
    centres = np.array([c.position_m for c in used])
    T_i = centres + delta_m * rotations[:, 1] - lambda_m * rotations[:, 2]
    T = np.median(T_i, axis=0)
    scatter2 = float(np.mean(np.sum((T_i - T) ** 2, axis=1)))
    sigma = math.sqrt(max(0.0, scatter2 - lambda_sigma_m**2) / len(used))
    return Tripod(tuple(float(v) for v in T), float(delta_m), sigma)


def provisional_tripod_for_run(cameras: list[Camera | None], graph) -> Tripod | None:
    """:func:`provisional_tripod` with the run's typical offsets: delta the solver's prior (0.2 m without one), lambda
    the measurements' mean and its sigma (:class:`~broadtrack_graph.graph.config.GraphConfig`)."""
    m = graph.measurements
    return provisional_tripod(cameras, graph.solver.tripod_delta_prior_m or 0.2, m.tripod_lambda_mean_m,
                              m.tripod_lambda_sigma_m or 0.0)


PER_FRAME_KEYS = ("residuals_m", "inliers", "axis_point_miss_m", "used_frames")
"""Keys of :func:`fit_tripod`'s info that hold one value per camera (left out of run summaries)."""


def fit_tripod_for_run(cameras: list[Camera | None], solver) -> tuple[Tripod | None, dict]:
    """:func:`fit_tripod` with the solver's delta prior; the info without its per-camera arrays.

    Args:
        cameras: trusted cameras of one tripod (None entries are skipped).
        solver: :class:`~broadtrack_graph.graph.config.SolverSettings` (``tripod_delta_prior_m``,
            ``tripod_delta_prior_sigma_m``).

    Returns:
        (tripod or None, summary info: inlier ratio, rms, condition, standard deviations, reason).
    """
    tripod, info = fit_tripod(cameras, delta_prior_m=solver.tripod_delta_prior_m,
                              delta_prior_sigma_m=solver.tripod_delta_prior_sigma_m)
    return tripod, {k: v for k, v in info.items() if k not in PER_FRAME_KEYS}
