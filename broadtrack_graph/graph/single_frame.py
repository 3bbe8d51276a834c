"""Robust refinement of ONE frame from its line points and keypoints (no flow).

Used for re-initialisation and single-frame calibration. Levenberg-Marquardt on
the shared builder's factors with graduated Cauchy scales (wide first, so that an
initial camera a few degrees / ~20 % focal off still pulls every point, then the
configured scale), the physical range prior on f and k1, a wide anchor on the
initial camera (keeps the problem well posed), and optionally the tripod factor.
"""

from __future__ import annotations

import logging

import gtsam
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.builder import GraphBuilder, graph_of
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.keys import camera_key
from broadtrack_graph.graph.noise import lm_params
from broadtrack_graph.types.observations import FrameObservations
from factors.keypoints import keypoint_residuals
from factors.lines import line_residuals
from factors.priors import make_anchor_factor

logger = logging.getLogger(__name__)

MIN_MEASUREMENTS = 4
"""Fewer line points + keypoints than this: the frame is not refined (camera None)."""


def refine_single_frame(
    initial: Camera,
    observations: FrameObservations,
    pitch: PitchTemplate,
    tripod: Tripod | None = None,
    config: GraphConfig | None = None,
    builder: GraphBuilder | None = None,
) -> tuple[Camera | None, dict]:
    """Robust (Cauchy) LM refinement of one camera from line points and keypoints.

    Args:
        initial: starting camera (any resolution: rescaled to the observations'); extra
            distortion terms beyond k1 are dropped (the state has k1 only).
        observations: the frame's line points (``lines_px``) and keypoints; flow is ignored.
        pitch: the pitch template.
        tripod: when given, the tripod factor ties the focal point to it; else C moves freely.
        config: sigmas; ``config.priors.k1_fixed`` holds k1 at the initial value, otherwise k1
            is free with the range prior keeping it in [k1_min, k1_max].
        builder: reuse a GraphBuilder of the same resolution/config (saves re-sampling the pitch).

    Returns:
        camera: refined camera at the observations' resolution, or None (info["reason"]).
        info: "cost" / "initial_cost" (final-scale robust cost), "iterations",
            "line_residuals_px" (N,) signed distances with "line_classes" (N,) class names,
            "keypoint_residuals_px" (M, 2), "inlier_ratio" (share of points within
            ``3 sigma``), "rms_inlier_px", "active_factors", "reason" (None when refined).
    """
    config = config or GraphConfig()
    W, H = observations.width_px, observations.height_px
    if builder is None or (builder.width_px, builder.height_px) != (W, H):
        builder = GraphBuilder(W, H, pitch, config)
    cfg = builder.config
    start = initial.rescaled(W, H)
    state0 = start.to_vector()
    uv, cls, names = builder.line_arrays(observations)
    kp = observations.keypoints
    kp_count = 0 if kp is None else len(kp)
    info: dict = {"reason": None, "dropped_extra_distortion": not start.extra_distortion.is_zero}
    if len(uv) + 2 * kp_count < MIN_MEASUREMENTS:
        info["reason"] = f"only {len(uv)} line points and {kp_count} keypoints"
        return None, info

    index = 0
    key = camera_key(index)
    final_scale_px = cfg.measurements.line_sigma_px * cfg.measurements.line_cauchy_sigmas
    stages = [s * W for s in cfg.solver.single_frame_cauchy_stages_per_width if s * W > final_scale_px] + [None]
    state = state0.copy()
    iterations = 0
    cost = initial_cost = float("nan")
    active: dict[str, int] = {}
    for stage, stage_scale in enumerate(stages):
        frame = builder.measurement_factors(observations, index, None, cauchy_scale_px=stage_scale)
        if stage < len(stages) - 2:
            # Coarse stages: only f and the angles move (C and k1 are weakly observable from
            # far off and would wander); the last two stages free everything.
            builder.prior_factors(index, frame, anchor_state=None)
            sigmas = cfg.priors.anchor_vector(state)
            sigmas[1] = cfg.priors.k1_fixed_sigma
            sigmas[5:8] = 1e-3
            frame.add("anchor", make_anchor_factor(key, np.r_[state[:1], state0[1:2], state[2:5], state0[5:8]], sigmas))
        else:
            builder.prior_factors(index, frame, anchor_state=state0)
        if tripod is not None:
            builder.tripod_factor(index, frame, tripod, variable=False)
        graph = graph_of(frame.factors)
        values = gtsam.Values()
        values.insert(key, state)
        if stage_scale is None:
            initial_cost = graph.error(values)
        optimizer = gtsam.LevenbergMarquardtOptimizer(graph, values, lm_params(cfg))
        result = optimizer.optimize()
        iterations += optimizer.iterations()
        state = result.atVector(key)
        if stage_scale is None:
            cost = graph.error(result)
            active = frame.active
    if not np.all(np.isfinite(state)) or state[0] <= 0:
        info["reason"] = "refinement diverged (non-finite or negative focal length)"
        return None, info
    camera = Camera.from_vector(state, W, H)
    line_r, _, line_valid = line_residuals(state, uv, cls, builder.polylines, W, H, want_jacobian=False)
    line_r = np.where(line_valid, line_r, np.nan)
    if kp_count:
        kp_r, _, kp_valid = keypoint_residuals(state, kp.uv_px, kp.points_w, W, H, want_jacobian=False)
        kp_r = np.where(kp_valid[:, None], kp_r, np.nan)
    else:
        kp_r = np.zeros((0, 2))
    distances = np.concatenate([np.abs(line_r), np.linalg.norm(kp_r, axis=1)])
    threshold = 3.0 * cfg.measurements.line_sigma_px
    inliers = np.isfinite(distances) & (distances < threshold)
    info.update(
        cost=float(cost),
        initial_cost=float(initial_cost),
        iterations=int(iterations),
        line_residuals_px=line_r,
        line_classes=np.array([names[j] for j in cls], dtype=object),
        keypoint_residuals_px=kp_r,
        inlier_ratio=float(inliers.mean()) if len(distances) else 0.0,
        rms_inlier_px=float(np.sqrt(np.mean(distances[inliers] ** 2))) if inliers.any() else float("nan"),
        active_factors=active,
    )
    return camera, info
