"""BatchRefiner: Levenberg-Marquardt over a clip (or a window of a match) with the tripod.

All frames' factors from the shared builder, the motion priors between consecutive
frames, and the tripod factor of every frame tied to ONE shared tripod variable
``[Tx, Ty, Tz, delta]`` that is re-estimated jointly with the trajectory (or held fixed).
Long inputs are refined in overlapping chunks (``config.solver.batch_chunk_frames``):
the tripod is estimated on the first chunk and then held fixed; never one LM over
a whole match (its linear system, time and memory would grow with every frame).
"""

from __future__ import annotations

import logging

import gtsam
import numpy as np
from tqdm import tqdm

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.builder import GraphBuilder, graph_of
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.estimates import EstimateSequence, FrameEstimate
from broadtrack_graph.graph.keys import camera_key, tripod_key
from broadtrack_graph.graph.noise import lm_params
from broadtrack_graph.graph.tripod_fit import fit_tripod_for_run
from broadtrack_graph.types.observations import FrameObservations
from factors.priors import make_anchor_factor

logger = logging.getLogger(__name__)


class BatchRefiner:
    """Offline refinement of a track.

    Args:
        width_px, height_px: resolution of observations and cameras.
        pitch: the pitch template.
        config: sigmas and solver settings.
    """

    def __init__(self, width_px: int, height_px: int, pitch: PitchTemplate, config: GraphConfig | None = None) -> None:
        self.config = config or GraphConfig()
        self.width_px, self.height_px = int(width_px), int(height_px)
        self.builder = GraphBuilder(width_px, height_px, pitch, self.config)
        self.last_info: dict = {}

    def refine(
        self,
        observations: list[FrameObservations],
        initial: EstimateSequence | list[Camera | None],
        tripod: Tripod | None = None,
        estimate_tripod: bool = True,
        progress: bool = False,
    ) -> tuple[EstimateSequence, Tripod | None]:
        """Refine every frame jointly (and the tripod).

        Args:
            observations: one FrameObservations per frame, in order.
            initial: starting cameras (a EstimateSequence or a list; None entries start from the nearest
                earlier camera). Frames flagged ``reinitialised`` in a EstimateSequence are not linked to
                their predecessor (no flow, no motion prior).
            tripod: starting / fixed tripod. With estimate_tripod and no tripod, it is fitted to
                the initial track (:func:`fit_tripod`); if that fails no tripod factor is used.
            estimate_tripod: True re-estimates (T, delta) jointly; False holds ``tripod`` fixed.
            progress: show a tqdm bar over chunks.

        Returns:
            (track with cameras, std and active factors per frame, tripod or None).
            ``self.last_info`` holds per-chunk costs, iterations and the tripod fit info.
        """
        frames = list(observations)
        start = self._starting_cameras(initial, len(frames))
        reinit = [bool(getattr(f, "reinitialised", False)) for f in initial] if isinstance(initial, EstimateSequence) else [False] * len(frames)
        info: dict = {"chunks": []}
        use_tripod = self.config.use_tripod
        if use_tripod and tripod is None and estimate_tripod:
            tripod, info["tripod_fit"] = fit_tripod_for_run(start, self.config.solver)
            if tripod is None:
                logger.warning("tripod fit failed (%s); refining without the tripod factor", info["tripod_fit"]["reason"])
        size = max(int(self.config.solver.batch_chunk_frames), 10)
        overlap = min(int(self.config.solver.batch_chunk_overlap_frames), size // 2)
        bounds = []
        lo = 0
        while lo < len(frames):
            hi = min(len(frames), lo + size)
            bounds.append((lo, hi))
            if hi == len(frames):
                break
            lo = hi - overlap
        estimates: list[FrameEstimate | None] = [None] * len(frames)
        variable = use_tripod and estimate_tripod and tripod is not None
        previous_chunk: dict[int, FrameEstimate] = {}
        for n, (lo, hi) in enumerate(tqdm(bounds, desc="batch refine", unit="chunk", disable=not progress)):
            chunk_start = [
                previous_chunk[i].camera if i in previous_chunk and previous_chunk[i].camera is not None else start[i]
                for i in range(lo, hi)
            ]
            anchor_first = chunk_start[0] if n > 0 else None
            chunk_estimates, tripod, chunk_info = self._refine_chunk(
                frames[lo:hi], chunk_start, reinit[lo:hi], tripod if use_tripod else None, variable and n == 0,
                anchor_first,
            )
            info["chunks"].append({"frames": [lo, hi], **chunk_info})
            keep_from = 0 if n == 0 else overlap // 2
            for i, est in enumerate(chunk_estimates[keep_from:], start=lo + keep_from):
                estimates[i] = est
            previous_chunk = {lo + i: est for i, est in enumerate(chunk_estimates)}
        self.last_info = info
        return EstimateSequence(estimates), tripod

    def refine_window(self, observations: list[FrameObservations], initial: EstimateSequence,
                      tripod: Tripod | None) -> list[FrameEstimate | None]:
        """One LM over a window of frames with the tripod held fixed and no link to a previous window.

        The unit of parallel refinement (:mod:`broadtrack_graph.track.chunked`): windows of a clip
        are independent, so they can run in any order or at once. Arguments as :meth:`refine`
        (``initial`` a EstimateSequence of the same length as ``observations``).

        Returns:
            One estimate per frame (camera None where LM gave a non-finite state).
        """
        frames = list(observations)
        start = self._starting_cameras(initial, len(frames))
        reinit = [bool(getattr(f, "reinitialised", False)) for f in initial]
        estimates, _, info = self._refine_chunk(frames, start, reinit, tripod if self.config.use_tripod else None,
                                                False, None)
        self.last_info = {"chunks": [{"frames": [0, len(frames)], **info}]}
        return estimates

    # ----------------------------------------------------------------- internals

    def _starting_cameras(self, initial, count: int) -> list[Camera]:
        cameras = initial.cameras() if isinstance(initial, EstimateSequence) else list(initial)
        if len(cameras) != count:
            raise ValueError(f"initial track has {len(cameras)} frames, observations have {count}")
        out: list[Camera | None] = []
        last = next((c for c in cameras if c is not None), None)
        if last is None:
            raise ValueError("initial track has no camera at all")
        for c in cameras:
            if c is not None:
                last = c.rescaled(self.width_px, self.height_px)
            out.append(last)
        return out

    def _refine_chunk(self, frames, start, reinit, tripod, estimate_tripod, anchor_first: Camera | None):
        b, cfg = self.builder, self.config
        factors = []
        active: list[dict] = []
        values = gtsam.Values()
        for i, obs in enumerate(frames):
            linked = i > 0 and not reinit[i]
            frame = b.measurement_factors(obs, i, i - 1 if linked else None)
            anchor = None if linked else start[i].to_vector()
            if i == 0 and anchor_first is not None:
                # Continue the previous chunk: its estimate of this (overlapping) frame, with the
                # random-walk sigmas, instead of the wide anchor of a fresh start.
                sigmas = cfg.motion.random_walk_vector()
                sigmas[0] *= anchor_first.focal_px  # relative zoom -> pixels
                frame.add("chunk_anchor", make_anchor_factor(camera_key(0), anchor_first.to_vector(), sigmas))
                anchor = None
            b.prior_factors(i, frame, anchor_state=anchor)
            if linked:
                before = i - 2 if i >= 2 and not reinit[i - 1] else None
                b.motion_factors(i, i - 1, before, frame)
                if cfg.priors.k1_fixed:
                    b.k1_fixed_factor(i, start[i].k1, start[i].to_vector(), frame)
            if tripod is not None:
                b.tripod_factor(i, frame, tripod, variable=estimate_tripod)
            factors += frame.factors
            active.append(frame.active)
            values.insert(camera_key(i), start[i].to_vector())
        if estimate_tripod:
            s = cfg.solver
            values.insert(tripod_key(), tripod.as_vector())
            # Weak prior on T around its start; delta towards the configured prior mean (or its start).
            mean = tripod.as_vector()
            sigmas = np.array([s.tripod_prior_T_m] * 3 + [1e3])
            if s.tripod_delta_prior_m is not None:
                mean[3] = s.tripod_delta_prior_m
                sigmas[3] = s.tripod_delta_prior_sigma_m
            factors.append(make_anchor_factor(tripod_key(), mean, sigmas))
        graph = graph_of(factors)
        initial_error = graph.error(values)
        optimizer = gtsam.LevenbergMarquardtOptimizer(graph, values, lm_params(cfg))
        result = optimizer.optimize()
        info = {"initial_cost": float(initial_error), "cost": float(graph.error(result)), "iterations": int(optimizer.iterations())}
        if estimate_tripod:
            tripod = Tripod.from_vector(result.atVector(tripod_key()))
        marginals = None
        if cfg.solver.compute_uncertainty:
            try:
                marginals = gtsam.Marginals(graph, result)
            except RuntimeError as exc:  # indeterminant system: report no std rather than fail
                logger.warning("marginals unavailable: %s", exc)
        estimates = []
        for i, obs in enumerate(frames):
            state = result.atVector(camera_key(i))
            if not np.all(np.isfinite(state)) or state[0] <= 0:
                estimates.append(FrameEstimate(obs.frame_index, None, None, active[i], reason="non-finite camera after LM"))
                continue
            std = None
            if marginals is not None:
                std = np.sqrt(np.clip(np.diag(marginals.marginalCovariance(camera_key(i))), 0.0, None))
            estimates.append(FrameEstimate(obs.frame_index, Camera.from_vector(state, self.width_px, self.height_px), std, active[i], reinitialised=reinit[i]))
        if estimate_tripod and marginals is not None:
            info["tripod_std"] = np.sqrt(np.clip(np.diag(marginals.marginalCovariance(tripod_key())), 0.0, None)).tolist()
        return estimates, tripod, info
