"""THE shared graph builder: one frame's observations -> GTSAM factors.

Used by every solver (single frame, online, fixed lag, batch) so that they all
optimise the same cost. One factor per (frame, measurement kind), never one per point.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass, field

import gtsam
import numpy as np

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.keys import camera_key, tripod_key
from broadtrack_graph.types.observations import FrameObservations
from factors.flow import make_flow_factor
from factors.keypoints import make_keypoint_factor
from factors.lines import MarkingPolylines, make_line_factor
from factors.motion import make_random_walk_factor, make_smoothness_factor
from factors.priors import make_anchor_factor, make_range_factor
from factors.tripod import make_fixed_tripod_factor, make_tripod_factor

logger = logging.getLogger(__name__)

MIN_LINE_POINTS = 1
"""A line factor is added when a frame has at least this many points on known classes."""


@dataclass
class FrameFactors:
    """The factors of one frame and the names of the active kinds.

    factors: list of gtsam factors to add.
    active: factor kind -> number of measurements (points, matches) or 1 for priors.
    line_classes: (N,) class index of each line point in the order of the line factor.
    """

    factors: list = field(default_factory=list)
    active: dict[str, int] = field(default_factory=dict)

    def add(self, kind: str, factor, count: int = 1) -> None:
        self.factors.append(factor)
        self.active[kind] = self.active.get(kind, 0) + count


class GraphBuilder:
    """Turns FrameObservations into factors for a given image size and pitch.

    Args:
        width_px, height_px: the resolution of observations and camera states.
        pitch: the pitch template.
        config: sigmas and settings.
    """

    def __init__(self, width_px: int, height_px: int, pitch: PitchTemplate, config: GraphConfig | None = None) -> None:
        self.width_px = int(width_px)
        self.height_px = int(height_px)
        self.pitch = pitch
        self.config = config or GraphConfig()
        m = self.config.measurements
        self.polylines = MarkingPolylines.from_pitch(pitch, m.line_step_m, m.arc_step_m)
        self._class_lookup = {name: i for i, name in enumerate(self.polylines.class_names)}
        self._warned_classes: set[str] = set()

    # ----------------------------------------------------------------- arrays

    def line_arrays(self, observations: FrameObservations) -> tuple[np.ndarray, np.ndarray, list[str]]:
        """Stack the line points of known classes.

        Returns:
            uv_px (N, 2), class_index (N,), class names in polyline index order (for reports).
        """
        uv_blocks, index_blocks = [], []
        for name, points in observations.lines_px.items():
            j = self._class_lookup.get(name.strip())
            points = np.asarray(points, dtype=float).reshape(-1, 2)
            if j is None:
                if name not in self._warned_classes:
                    logger.info("class %r has no 3D element; its points are not used", name)
                    self._warned_classes.add(name)
                continue
            finite = np.all(np.isfinite(points), axis=1)
            if len(points[finite]):
                uv_blocks.append(points[finite])
                index_blocks.append(np.full(int(finite.sum()), j))
        if not uv_blocks:
            return np.zeros((0, 2)), np.zeros(0, dtype=int), list(self.polylines.class_names)
        return np.vstack(uv_blocks), np.concatenate(index_blocks), list(self.polylines.class_names)

    def _check_size(self, observations: FrameObservations) -> None:
        if (observations.width_px, observations.height_px) != (self.width_px, self.height_px):
            raise ValueError(
                f"frame {observations.frame_index}: observations are {observations.width_px}x{observations.height_px}, "
                f"the graph works at {self.width_px}x{self.height_px}; rescale them first"
            )

    # ----------------------------------------------------------------- factors

    def measurement_factors(
        self,
        observations: FrameObservations,
        frame_index: int,
        previous_index: int | None,
        cauchy_scale_px: float | None = None,
    ) -> FrameFactors:
        """Lines, keypoints and flow (flow only when previous_index is given).

        Args:
            observations: the frame's measurements.
            frame_index: index used for the camera key of this frame.
            previous_index: index of the previous frame's camera, or None to drop flow.
            cauchy_scale_px: override of the Cauchy scale in pixels (graduated refinement).
        """
        self._check_size(observations)
        cfg, m = self.config, self.config.measurements
        out = FrameFactors()
        key = camera_key(frame_index)

        def scale(sigma_px: float, sigmas: float) -> float:
            return sigmas if cauchy_scale_px is None else cauchy_scale_px / sigma_px

        if cfg.use_lines:
            uv, cls, _ = self.line_arrays(observations)
            if len(uv) >= MIN_LINE_POINTS:
                out.add("lines", make_line_factor(
                    key, uv, cls, self.polylines, self.width_px, self.height_px, m.line_sigma_px,
                    scale(m.line_sigma_px, m.line_cauchy_sigmas), m.line_loss,
                ), len(uv))
        kp = observations.keypoints
        if cfg.use_keypoints and kp is not None and len(kp) > 0:
            out.add("keypoints", make_keypoint_factor(
                key, kp.uv_px, kp.points_w, kp.confidence, self.width_px, self.height_px, m.keypoint_sigma_px,
                scale(m.keypoint_sigma_px, m.keypoint_cauchy_sigmas),
            ), len(kp))
        flow = observations.flow
        if cfg.use_flow and previous_index is not None and flow is not None and len(flow) > 0:
            out.add("flow", make_flow_factor(
                camera_key(previous_index), key, flow.uv_prev_px, flow.uv_cur_px, self.width_px, self.height_px,
                m.flow_sigma_px, scale(m.flow_sigma_px, m.flow_cauchy_sigmas),
            ), len(flow))
        return out

    def prior_factors(self, frame_index: int, out: FrameFactors, anchor_state: np.ndarray | None = None,
                      anchor_position_m: float | None = None) -> FrameFactors:
        """Range prior on f and k1 (always), k1 held fixed if configured, anchor when given (its focal point's sigma
        ``anchor_position_m``, default the priors' ``anchor_position_m``)."""
        p = self.config.priors
        key = camera_key(frame_index)
        out.add("range_prior", make_range_factor(
            key, p.focal_range_px(self.width_px), (p.k1_min, p.k1_max), p.focal_edge_sigma_rel, p.k1_edge_sigma,
            p.k1_mean, p.k1_sigma,
        ))
        if anchor_state is not None:
            sigmas = p.anchor_vector(anchor_state, anchor_position_m)
            if p.k1_fixed:
                sigmas[1] = p.k1_fixed_sigma
            out.add("anchor", make_anchor_factor(key, anchor_state, sigmas))
        return out

    def k1_fixed_factor(self, frame_index: int, k1: float, state_like: np.ndarray, out: FrameFactors) -> FrameFactors:
        """Tight prior holding k1 (used when k1_fixed and the frame has no anchor)."""
        p = self.config.priors
        sigmas = np.full(8, 1e6)
        sigmas[1] = p.k1_fixed_sigma
        state0 = np.asarray(state_like, dtype=float).copy()
        state0[1] = k1
        out.add("k1_fixed", make_anchor_factor(camera_key(frame_index), state0, sigmas))
        return out

    def motion_factors(self, frame_index: int, previous_index: int, before_previous: int | None, out: FrameFactors) -> FrameFactors:
        """Random walk to the previous frame, and the smoothness factor when two predecessors exist."""
        mot = self.config.motion
        out.add("motion", make_random_walk_factor(camera_key(previous_index), camera_key(frame_index), mot.random_walk_vector()))
        if mot.use_smoothness and before_previous is not None:
            out.add("smoothness", make_smoothness_factor(
                camera_key(before_previous), camera_key(previous_index), camera_key(frame_index), mot.smoothness_vector(),
            ))
        return out

    def tripod_factor(self, frame_index: int, out: FrameFactors, tripod: Tripod | None, variable: bool = False) -> FrameFactors:
        """Tripod factor: to the shared tripod variable (batch) or to a fixed tripod (online).

        With a fixed tripod the focal point's place on the optical axis gets its prior
        (``tripod_lambda_*``); with the tripod a variable it does not: there, a lambda prior
        whose mean is off for the lens moves T along the axis and, through the height, delta.
        A fixed tripod's own uncertainty (``Tripod.sigma_m``: a provisional tripod's, from opening frames that disagree
        where the camera stands) adds to the factor's sigma and to the lambda prior's: it holds the camera only as
        firmly as they agree.
        """
        if not self.config.use_tripod:
            return out
        m = self.config.measurements
        sigma = m.tripod_sigma_m
        zoom = None if m.tripod_lambda_sigma_m is None else (m.tripod_lambda_mean_m, m.tripod_lambda_sigma_m)
        if variable:
            out.add("tripod", make_tripod_factor(camera_key(frame_index), tripod_key(), sigma, m.tripod_model))
        elif tripod is not None:
            if tripod.sigma_m > 0:
                sigma = float(np.hypot(sigma, tripod.sigma_m))
                zoom = None if zoom is None else (zoom[0], float(np.hypot(zoom[1], tripod.sigma_m)))
            out.add("tripod", make_fixed_tripod_factor(camera_key(frame_index), tripod.as_vector(), sigma, m.tripod_model, zoom))
        return out


def graph_of(factors) -> gtsam.NonlinearFactorGraph:
    """A NonlinearFactorGraph holding the given factors."""
    graph = gtsam.NonlinearFactorGraph()
    for factor in factors:
        graph.add(factor)
    return graph
