"""One streaming-solver interface over the online tracker and the fixed-lag smoother.

The tracking loop pushes each frame and gets (the frame's current estimate, the
estimates released now), whatever the mode: online releases every frame at once,
fixed-lag releases a frame L frames later. When GTSAM rejects an update the solver
is rebuilt and the frame re-added as a fresh start (see :meth:`StreamingSolver.push`).
"""

from __future__ import annotations

import logging
from dataclasses import replace

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.estimates import FrameEstimate
from broadtrack_graph.graph.fixed_lag import FixedLagSmoother
from broadtrack_graph.graph.online import OnlineTracker
from broadtrack_graph.types.observations import FrameObservations

log = logging.getLogger(__name__)

SOLVER_ERRORS = (RuntimeError, IndexError, ValueError)
"""What GTSAM raises on an ill-posed update or a key already marginalised (the solver is then rebuilt)."""


class StreamingSolver:
    """A solver fed one frame at a time: push a frame, get finished estimates.

    When GTSAM rejects an update (an indeterminate system after a bad re-initialisation),
    the solver is rebuilt and the frame is added again as a fresh start; frames still
    waiting in the old fixed-lag window are released as they were or reported failed.

    Subclasses build their solver in :meth:`_build` (for a tripod), add a frame in
    :meth:`_add` and release the frames they still hold in :meth:`finish`.

    Args:
        width_px, height_px: resolution of the observations and cameras.
        pitch: the pitch template.
        graph: sigmas and solver settings.
        tripod: a known tripod held fixed in the tripod factor, or None.

    Attributes:
        rebuilds: how many times the solver was rebuilt after a GTSAM error.
    """

    def __init__(self, width_px: int, height_px: int, pitch: PitchTemplate, graph: GraphConfig,
                 tripod: Tripod | None) -> None:
        self.width_px, self.height_px = width_px, height_px
        self.pitch = pitch
        self.graph = graph
        self.rebuilds = 0
        self.tracker: OnlineTracker
        self._build(tripod)

    # ----------------------------------------------------------------- what a mode provides

    def _build(self, tripod: Tripod | None) -> None:
        """(Re)create the underlying solver with this tripod; sets ``self.tracker``."""
        raise NotImplementedError

    def _add(self, observations: FrameObservations, guess: Camera | None,
             trust_previous: bool) -> tuple[FrameEstimate, list[FrameEstimate]]:
        """Add one frame: (its current filtered estimate, the estimates released now)."""
        raise NotImplementedError

    def finish(self) -> list[FrameEstimate]:
        """Release every frame still held (oldest first)."""
        raise NotImplementedError

    # ----------------------------------------------------------------- the shared interface

    @property
    def tripod(self) -> Tripod | None:
        """The tripod held fixed in the tripod factor (None: no tripod term); settable."""
        return self.tracker.tripod

    @tripod.setter
    def tripod(self, tripod: Tripod | None) -> None:
        self.tracker.tripod = tripod

    def reset(self, camera: Camera) -> None:
        """Re-anchor on a camera: the next frame is not linked to the previous one."""
        self.tracker.reset(camera)

    def hold_position_next(self) -> None:
        """The next restarted frame holds its focal point near its starting camera's
        (:meth:`~broadtrack_graph.graph.online.OnlineTracker.hold_position_next`)."""
        self.tracker.hold_position_next()

    def replace_last(self, camera: Camera) -> None:
        """The last frame's camera, re-initialised after its update: the next frame is linked to it
        (:meth:`~broadtrack_graph.graph.online.OnlineTracker.replace_last`)."""
        self.tracker.replace_last(camera)

    def push(self, observations: FrameObservations, guess: Camera | None, trust_previous: bool,
             fallback: Camera | None = None) -> tuple[FrameEstimate, list[FrameEstimate]]:
        """Add one frame. Returns (current filtered estimate, estimates released now, oldest first).

        On a GTSAM error (``SOLVER_ERRORS``): log it, release what the old window held, rebuild
        (same tripod), and add the frame again without flow as a fresh start from ``guess``
        (else ``fallback``) under the wide anchor: a start the frame's markings cannot hold (a wrong
        re-initialisation) then moves, and its confidence tells. Without a camera to start from, or when that fails too, the frame's
        estimate is a failed FrameEstimate (camera None, with the reason) and is released at once.

        Args:
            observations: the frame's measurements (at the solver's resolution).
            guess: starting camera (a re-initialisation), or None to continue from the last estimate.
            trust_previous: False: no link (flow, motion prior) to the previous frame.
            fallback: camera to restart from if the solver fails (default: guess).
        """
        try:
            return self._add(observations, guess, trust_previous)
        except SOLVER_ERRORS as exc:
            start = guess or fallback
            log.warning("frame %d: solver update failed (%s); restarting the solver",
                        observations.frame_index, str(exc).strip().splitlines()[0] if str(exc).strip() else "error")
            try:
                released = self.finish()
            except SOLVER_ERRORS:
                released = []
            self._build(self.tripod)
            self.rebuilds += 1
            if start is None:
                failed = FrameEstimate(observations.frame_index, None, reason="solver failed and no camera to restart from")
                return failed, released + [failed]
            try:
                current, more = self._add(replace(observations, flow=None), start, False)
            except SOLVER_ERRORS:
                self._build(self.tripod)
                failed = FrameEstimate(observations.frame_index, None, reason="solver failed twice on this frame")
                return failed, released + [failed]
            return current, released + more


class OnlineStreamingSolver(StreamingSolver):
    """iSAM2 online: every frame's estimate is released as soon as it is added."""

    def _build(self, tripod: Tripod | None) -> None:
        self.tracker = OnlineTracker(self.width_px, self.height_px, self.pitch, self.graph, tripod)

    def _add(self, observations, guess, trust_previous):
        current = self.tracker.add_frame(observations, guess, trust_previous)
        return current, [current]

    def finish(self) -> list[FrameEstimate]:
        return []


class FixedLagStreamingSolver(StreamingSolver):
    """Fixed-lag smoothing: a frame's estimate is released ``lag`` frames after it was added.

    Args:
        lag: L, future frames used before a frame is released (>= 1).
        others: as :class:`StreamingSolver`.
    """

    def __init__(self, width_px: int, height_px: int, pitch: PitchTemplate, graph: GraphConfig,
                 tripod: Tripod | None, lag: int) -> None:
        self.lag = lag
        super().__init__(width_px, height_px, pitch, graph, tripod)

    def _build(self, tripod: Tripod | None) -> None:
        self.smoother = FixedLagSmoother(self.width_px, self.height_px, self.pitch, self.graph, tripod, lag=self.lag)
        self.tracker = self.smoother.tracker

    def _add(self, observations, guess, trust_previous):
        released = self.smoother.add_frame(observations, guess, trust_previous)
        current = self.tracker.estimate(self.tracker.last_step, observations.frame_index)
        return current, released

    def finish(self) -> list[FrameEstimate]:
        return self.smoother.finish()
