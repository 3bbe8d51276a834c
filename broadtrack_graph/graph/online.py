"""OnlineTracker: one iSAM2 update per frame, the current frame's estimate at once.

Runs on GTSAM's ``IncrementalFixedLagSmoother`` (iSAM2 underneath) keeping a window
of ``config.solver.window_frames`` frames: older camera states are marginalised, so
the per-frame cost and memory stay flat over a whole match (plain iSAM2 over a
growing graph slows without bound). Each frame starts from the previous
estimate (random walk on the focal point, no constant-velocity guess).

The tripod is held fixed here (estimate it with :class:`~broadtrack_graph.graph.batch.BatchRefiner`
or :func:`~broadtrack_graph.graph.tripod_fit.fit_tripod` on an opening segment, then pass it).
"""

from __future__ import annotations

import logging

import gtsam
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.builder import FrameFactors, GraphBuilder, graph_of
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.estimates import FrameEstimate
from broadtrack_graph.graph.keys import camera_key
from broadtrack_graph.graph.noise import isam2_params
from broadtrack_graph.types.observations import FrameObservations
from factors.flow import flow_residuals
from factors.priors import make_anchor_factor
from factors.robust import cauchy_weight

logger = logging.getLogger(__name__)


class OnlineTracker:
    """Incremental camera tracker over a stream of FrameObservations.

    Args:
        width_px, height_px: resolution of the observations and cameras.
        pitch: the pitch template.
        config: sigmas and solver settings.
        tripod: a known tripod (fixed tripod factor on every frame), or None. The ``tripod``
            attribute may be set later (e.g. after fitting it on an opening segment); it applies
            to the frames added from then on.
        window_frames: override of ``config.solver.window_frames`` (frames kept in the smoother).

    Usage::

        tracker = OnlineTracker(960, 540, PitchTemplate(), tripod=tripod)
        first = tracker.add_frame(observations[0], initial_guess=camera0)
        for obs in observations[1:]:
            estimate = tracker.add_frame(obs)

    After a re-initialisation by the front end, call ``add_frame(obs, initial_guess=camera,
    trust_previous=False)`` (or :meth:`reset` then ``add_frame``): the frame gets no flow and
    no motion prior to its predecessor, only an anchor on the given camera.
    """

    def __init__(
        self,
        width_px: int,
        height_px: int,
        pitch: PitchTemplate,
        config: GraphConfig | None = None,
        tripod: Tripod | None = None,
        window_frames: int | None = None,
    ) -> None:
        self.config = config or GraphConfig()
        self.builder = GraphBuilder(width_px, height_px, pitch, self.config)
        self.width_px, self.height_px = int(width_px), int(height_px)
        self.tripod = tripod
        self.window_frames = int(window_frames or self.config.solver.window_frames)
        if self.window_frames < 3:
            raise ValueError(f"window_frames must be >= 3, got {self.window_frames}")
        self._smoother = gtsam.IncrementalFixedLagSmoother(float(self.window_frames), isam2_params(self.config))
        self._step = -1  # internal sequence number of the last frame (keys and timestamps)
        self._linked_steps = 0  # consecutive linked frames ending at the last one
        self._last_state: np.ndarray | None = None
        self._pending_reset: Camera | None = None
        self._hold_position = False  # the next restarted frame holds its focal point (hold_position_next)
        self._active: dict[int, dict[str, int]] = {}  # step -> active factor kinds, for the window

    # ----------------------------------------------------------------- public

    @property
    def last_step(self) -> int:
        """Internal step of the last added frame (-1 before the first)."""
        return self._step

    def reset(self, camera: Camera) -> None:
        """Re-anchor on a camera: the next frame is not linked to the previous one."""
        self._pending_reset = camera

    def replace_last(self, camera: Camera) -> None:
        """The last frame's camera, re-initialised after its update: the next frame is linked to it (optical flow
        and motion prior) as to a tracked frame's.

        The camera enters the window as a state of its own and becomes the previous state, held on it by a prior of
        one frame's motion (the random walk's sigmas) but for its focal point, held within
        ``PriorSigmas.restart_position_m`` unless a tripod holds it. No marking of the frame is attached to that
        state: the camera, fitted to them, stands for them, and under the wide anchor the next frames' lines alone
        walked its focal point off during fast pans. Re-anchoring the next frame on it instead (:meth:`reset`) would
        leave that frame alone against what one frame barely tells apart (focal length against distance, k1).
        """
        self._pending_reset = None
        camera = camera.rescaled(self.width_px, self.height_px)
        state = camera.to_vector()
        sigmas = self.config.motion.random_walk_vector()
        sigmas[0] *= state[0]  # relative zoom -> pixels
        held_m = None if self.tripod is not None else self.config.priors.restart_position_m
        sigmas[5:8] = self.config.priors.anchor_vector(state, held_m)[5:8]
        if self.config.priors.k1_fixed:
            sigmas[1] = self.config.priors.k1_fixed_sigma
        step = self._step + 1
        frame = FrameFactors()
        frame.add("anchor", make_anchor_factor(camera_key(step), state, sigmas))
        values = gtsam.Values()
        values.insert(camera_key(step), state)
        self._smoother.update(graph_of(frame.factors), values, {camera_key(step): float(step)})
        self._step = step
        self._linked_steps = 1
        self._last_state = self._smoother.calculateEstimateVector(camera_key(step))
        self._active[step] = frame.active
        self._active.pop(step - self.window_frames - 2, None)

    def hold_position_next(self) -> None:
        """The next restarted frame holds its focal point within ``PriorSigmas.restart_position_m`` of its starting
        camera (unless a tripod holds it): a camera whose place is known. A zoomed view showing two or three markings
        leaves focal length against distance along the line of sight open; held, it is solved."""
        self._hold_position = True

    def _restart_position_m(self) -> float | None:
        """The focal point's sigma (metres) in a (re)started frame's anchor: None (the anchor's own) unless held
        (:meth:`hold_position_next`) without a tripod."""
        if not self._hold_position or self.tripod is not None:
            return None
        return self.config.priors.restart_position_m

    def add_frame(
        self, observations: FrameObservations, initial_guess: Camera | None = None, trust_previous: bool = True
    ) -> FrameEstimate:
        """Add one frame and return its estimate (filtered: uses this and past frames only).

        Args:
            observations: the frame's measurements (at the tracker's resolution).
            initial_guess: starting camera; required for the first frame. With
                trust_previous=True it only replaces the starting point.
            trust_previous: False drops the link to the previous frame (no flow, no motion
                prior) and anchors the frame on initial_guess (or the last estimate).

        Returns:
            FrameEstimate (camera, std in state order, active factors).
        """
        step = self.insert(observations, initial_guess, trust_previous)
        return self.estimate(step, observations.frame_index)

    def estimate(self, step: int, frame_index: int) -> FrameEstimate:
        """Current estimate of an internal step (from :meth:`insert`) still inside the window.

        Raises:
            RuntimeError (from GTSAM) when the step has already been marginalised.
        """
        key = camera_key(step)
        state = self._smoother.calculateEstimateVector(key)
        active = self._active.get(step, {})
        if not np.all(np.isfinite(state)) or state[0] <= 0:
            return FrameEstimate(frame_index, None, None, active, reason="solver produced a non-finite camera")
        std = None
        if self.config.solver.compute_uncertainty:
            std = np.sqrt(np.clip(np.diag(self._smoother.marginalCovariance(key)), 0.0, None))
        return FrameEstimate(frame_index, Camera.from_vector(state, self.width_px, self.height_px), std, active)

    # ----------------------------------------------------------------- internals

    def _predict(self, previous_state: np.ndarray, observations: FrameObservations) -> np.ndarray:
        """Starting state of a linked frame: the previous estimate moved by the flow.

        A few robust Gauss-Newton steps on the flow matches alone (previous camera fixed)
        with the random-walk prior as regulariser, so that the frame's factors are
        linearised close to their optimum and iSAM2 rarely needs to relinearise the window.
        """
        flow = observations.flow
        iterations = self.config.solver.prediction_iterations
        if flow is None or len(flow) == 0 or iterations <= 0 or not self.config.use_flow:
            return previous_state
        m = self.config.measurements
        sigmas = self.config.motion.random_walk_vector().copy()
        sigmas[0] *= previous_state[0]  # relative zoom -> pixels
        if self.config.priors.k1_fixed:
            sigmas[1] = self.config.priors.k1_fixed_sigma
        prior_info = 1.0 / sigmas**2
        x = previous_state.copy()
        for _ in range(iterations):
            r, (_, J), valid = flow_residuals(previous_state, x, flow.uv_prev_px, flow.uv_cur_px, self.width_px,
                                              self.height_px, previous_fixed=True)
            if valid.sum() < 8:
                return previous_state
            r = r[valid] / m.flow_sigma_px
            J = J[valid] / m.flow_sigma_px
            w = cauchy_weight(np.einsum("nd,nd->n", r, r), m.flow_cauchy_sigmas)
            Jf = J.reshape(-1, 8)
            wf = np.repeat(w, 2)
            H = Jf.T @ (Jf * wf[:, None]) + np.diag(prior_info)
            g = Jf.T @ (wf * r.reshape(-1)) + prior_info * (x - previous_state)
            step = -np.linalg.solve(H, g)
            x = x + step
            if not np.all(np.isfinite(x)) or x[0] <= 0:
                return previous_state
        return x

    def insert(self, observations: FrameObservations, initial_guess: Camera | None = None, trust_previous: bool = True) -> int:
        """Add one frame to the smoother without reading its estimate; returns its internal step.

        Same arguments as :meth:`add_frame` (the fixed-lag smoother reads older steps later).
        """
        if self._pending_reset is not None:
            initial_guess = initial_guess or self._pending_reset
            trust_previous = False
            self._pending_reset = None
        step = self._step + 1
        if self._last_state is None and initial_guess is None:
            raise ValueError("the first frame needs an initial_guess camera")
        if initial_guess is not None:
            guess = initial_guess.rescaled(self.width_px, self.height_px)
            start = guess.to_vector()
        else:
            start = self._last_state.copy()
        linked = trust_previous and self._last_state is not None
        if linked and initial_guess is None:
            start = self._predict(start, observations)
        previous = step - 1 if linked else None
        frame = self.builder.measurement_factors(observations, step, previous)
        self.builder.prior_factors(step, frame, anchor_state=None if linked else start,
                                   anchor_position_m=self._restart_position_m())
        if not linked:
            self._hold_position = False
        if linked:
            before = step - 2 if self._linked_steps >= 2 else None
            self.builder.motion_factors(step, step - 1, before, frame)
            if self.config.priors.k1_fixed:
                self.builder.k1_fixed_factor(step, self._last_state[1], start, frame)
        if self.tripod is not None:
            self.builder.tripod_factor(step, frame, self.tripod, variable=False)
        values = gtsam.Values()
        values.insert(camera_key(step), start)
        timestamps = {camera_key(step): float(step)}
        self._smoother.update(graph_of(frame.factors), values, timestamps)
        for _ in range(self.config.solver.extra_iterations_per_frame):
            self._smoother.update()
        self._step = step
        self._linked_steps = self._linked_steps + 1 if linked else 1
        self._last_state = self._smoother.calculateEstimateVector(camera_key(step))
        self._active[step] = frame.active
        self._active.pop(step - self.window_frames - 2, None)
        return step
