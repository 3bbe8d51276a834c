"""FixedLagSmoother: the online stream, each frame's estimate released L frames later.

The estimate of frame t is taken from the incremental smoother once frames
t+1 .. t+L have been added, so it uses L frames of future measurements (flow and
motion priors tie them together). The internal window is at least L + 3 frames.
"""

from __future__ import annotations

from collections import deque

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.estimates import EstimateSequence, FrameEstimate
from broadtrack_graph.graph.online import OnlineTracker
from broadtrack_graph.types.observations import FrameObservations


class FixedLagSmoother:
    """Lagged smoother over a stream of FrameObservations.

    Args:
        width_px, height_px, pitch, config, tripod: as :class:`OnlineTracker`.
        lag: L, number of future frames used before a frame's estimate is released (>= 1).

    Usage::

        smoother = FixedLagSmoother(960, 540, pitch, lag=25)
        track = EstimateSequence()
        for i, obs in enumerate(stream):
            track.frames += smoother.add_frame(obs, initial_guess=camera0 if i == 0 else None)
        track.frames += smoother.finish()
    """

    def __init__(
        self,
        width_px: int,
        height_px: int,
        pitch: PitchTemplate,
        config: GraphConfig | None = None,
        tripod: Tripod | None = None,
        lag: int = 25,
    ) -> None:
        if lag < 1:
            raise ValueError(f"lag must be >= 1 frame, got {lag}")
        config = config or GraphConfig()
        self.lag = int(lag)
        window = max(config.solver.window_frames, self.lag + 3)
        self._tracker = OnlineTracker(width_px, height_px, pitch, config, tripod, window_frames=window)
        self._pending: deque[tuple[int, int]] = deque()  # (step, frame_index)

    @property
    def tracker(self) -> OnlineTracker:
        """The underlying online tracker (its ``estimate(last_step, ...)`` is the filtered current frame;
        its ``tripod`` may be set once estimated)."""
        return self._tracker

    def reset(self, camera: Camera) -> None:
        """Re-anchor on a camera (see :meth:`OnlineTracker.reset`)."""
        self._tracker.reset(camera)

    def add_frame(
        self, observations: FrameObservations, initial_guess: Camera | None = None, trust_previous: bool = True
    ) -> list[FrameEstimate]:
        """Add one frame; return the estimates that became final (the frame L steps back), oldest first."""
        step = self._tracker.insert(observations, initial_guess, trust_previous)
        self._pending.append((step, observations.frame_index))
        out = []
        while self._pending and self._pending[0][0] <= step - self.lag:
            old_step, frame_index = self._pending.popleft()
            out.append(self._tracker.estimate(old_step, frame_index))
        return out

    def finish(self) -> list[FrameEstimate]:
        """Release the last L estimates (with the future available, i.e. fewer than L frames)."""
        out = [self._tracker.estimate(step, frame_index) for step, frame_index in self._pending]
        self._pending.clear()
        return out

    def run(self, observations, initial_guess: Camera) -> EstimateSequence:
        """Convenience: smooth a whole iterable of observations starting from initial_guess."""
        track = EstimateSequence()
        for i, obs in enumerate(observations):
            track.frames += self.add_frame(obs, initial_guess=initial_guess if i == 0 else None)
        track.frames += self.finish()
        return track
