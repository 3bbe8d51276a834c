"""The current chain of a tracking run and the trust it has earned, in one owner.

A chain is the frames linked to each other since a re-initialisation (or the first frame): each is solved from
the one before (flow, motion prior). A cut, a frame without a pitch, a failed detection or a lost frame breaks it.
:class:`Chain` holds what the run knows of its chain:

- the **camera id** it belongs to (the broadcast camera; None until known), and through it which camera's tripod
  the solver holds (the online tripod is told of a new id here, :meth:`Chain.identify`);
- whether it is **trusted** (a frame reached the bar) and since which frame, and the **bar** itself: the
  confidence threshold, or more for a new shot's camera (a first frame can be explained, nearly as well, by a
  wrong camera);
- whether its re-initialisation **continued** a confident camera's chain (a refined guess: the trust goes on; a
  better camera of the same id replacing a trusted chain's held camera mid-shot keeps the trust too);
- whether the run is **lost** (the next frame is re-initialised) and how many frames in a row were **carried** on
  the motion prior alone;
- how many of its scored frames reached the **tripod's bar** (``tripod_fit_min_confidence``): a chain under it on
  most of its frames, with no tripod holding its focal point, writes only its frames at the bar
  (:mod:`~broadtrack_graph.track.judge`, rule 7);
- whether its frames take the **faint look** (:mod:`~broadtrack_graph.detect.faint_lines`): a chain whose first
  camera the court model found on its frame's faint look keeps it while that camera is under the chain's bar
  without it.

Everything else asks it: the re-initialisation policy reads the camera id and the trust, the judge
(:mod:`~broadtrack_graph.track.judge`) is given the trust, the frame loop tells it what happened. No I/O.
"""

from __future__ import annotations

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.track.camera_ids import CameraRegistry
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.online_tripod import OnlineTripod
from broadtrack_graph.track.reinit_decision import ReinitDecision


class Chain:
    """The trust state of a run's current chain (module docstring).

    Args:
        config: the thresholds (``confidence_threshold``, ``reinit_switch_margin``, ``max_motion_prior_frames``).
        registry: the run's cameras by id (where a camera stands names it).
        tripod: the run's online tripod, told when the chain's camera changes; None: no tripod to keep (the
            re-initialisation policy on its own, as the placement benchmarks and the policy's tests ask it).
        solver: holds the tripod in use (anything with a settable ``tripod``); with ``tripod``.

    Attributes:
        camera_id: the camera id of the chain (None: not known yet).
        trusted: a frame of the chain reached the bar; trusted_since: the first such frame (None: not trusted).
        trust_at: the confidence that trusts the chain (its bar while it is not trusted).
        continued: the chain was started by a re-initialisation that continues a confident camera's chain.
        lost: no chain: the next frame is re-initialised.
        carried: frames in a row carried on the motion prior alone.
        faint_look: the chain's frames take the faint look (detect.faint_lines): its first camera needed it to be
            confident (set by the frame loop).
        frames_rated, frames_sure: the chain's frames scored so far (:meth:`rated`), and those at the tripod's bar.
    """

    def __init__(self, config: TrackingConfig, registry: CameraRegistry, tripod: OnlineTripod | None = None,
                 solver=None) -> None:
        self.config, self.registry = config, registry
        self._tripod, self._solver = tripod, solver
        self.camera_id: str | None = None
        self.trusted = False
        self.trusted_since: int | None = None
        self.trust_at = config.confidence_threshold
        self.continued = False
        self.lost = True
        self.carried = 0
        self.faint_look = False
        self.frames_rated = 0
        self.frames_sure = 0

    # ----------------------------------------------------------------- the camera id

    def new_stretch(self) -> None:
        """A cut or a view change: the chain's camera is not known (its tripod stays in the solver till one is)."""
        self.camera_id = None

    def identify(self, camera_id: str) -> None:
        """The frames from now on are camera ``camera_id``'s: its tripod (and guesses) from now on."""
        if self._tripod is not None:
            self._tripod.switch(self._solver, camera_id)
        self.camera_id = camera_id

    def identify_at(self, camera: Camera) -> None:
        """A confident camera of a chain whose camera is not known yet: the id of where it stands (a new id when no
        known camera stands there)."""
        if self.camera_id is None:
            self.identify(self.registry.identify(camera.position_m, camera.R_cw[2]))

    @property
    def place_known(self) -> bool:
        """The chain's camera id is known and trusted: where that camera stands is known (a restart holds it there)."""
        return self.camera_id is not None and self.camera_id not in self.registry.untrusted

    def settled_tripod(self) -> Tripod | None:
        """The tripod of the chain's camera once fitted or given (not the provisional one), or None."""
        if self.camera_id is None or self._tripod is None or self._tripod.provisional:
            return None
        return self._solver.tripod

    # ----------------------------------------------------------------- starting, extending, breaking

    def start(self, decision: ReinitDecision) -> None:
        """Restarting from a re-initialisation's camera: its camera id (and that camera's tripod) from now on.

        A decision that does not continue a confident camera's chain starts a new chain: not trusted, its bar the
        threshold, plus the margin for a new shot's camera (:attr:`ReinitDecision.new_camera`); a bar raised for
        the chain it replaces stays raised while that chain was never trusted. Except mid-shot: a camera of the
        trusted chain's own camera id that replaces its held camera (the policy switches only to a better one)
        keeps the trust, since the held camera's frames were being written.
        """
        replaces_trusted = (self.trusted and not self.lost and not decision.new_camera
                            and decision.camera_id is not None and decision.camera_id == self.camera_id)
        if decision.camera_id is not None and decision.camera_id != self.camera_id:
            self.identify(decision.camera_id)
        elif decision.camera_id is None and self.camera_id is None and self._tripod is not None:
            self._tripod.release(self._solver)  # not identified yet (untrusted): no other camera's tripod
        if not decision.continues_chain:
            self.frames_rated = self.frames_sure = 0
            if self._tripod is not None:  # the cameras collected for a tripod elsewhere are dropped
                self._tripod.new_chain(self._solver, decision.camera, self.registry)
            if not replaces_trusted:
                bar = self.config.confidence_threshold + self.config.reinit_switch_margin * decision.new_camera
                self.trust_at = bar if self.trusted else max(self.trust_at, bar)
                self.trusted, self.trusted_since = False, None
        self.continued = decision.continues_chain

    def mostly_sure(self, confidence: float | None) -> bool:
        """With a frame at ``confidence`` added (None: not scored), at least half the chain's scored frames reach the
        tripod's bar."""
        scored = confidence is not None
        return 2 * (self.frames_sure + (scored and self._at_tripod_bar(confidence))) >= self.frames_rated + scored

    def rated(self, confidence: float) -> None:
        """One more of the chain's frames was scored, at ``confidence``."""
        self.frames_rated += 1
        self.frames_sure += self._at_tripod_bar(confidence)

    def _at_tripod_bar(self, confidence: float) -> bool:
        return confidence >= self.config.tripod_fit_min_confidence

    def trust(self, frame_index: int) -> None:
        """A frame at the bar: the chain is trusted (since this frame, if it was not)."""
        if not self.trusted:
            self.trusted, self.trusted_since = True, frame_index

    def goes_on(self) -> None:
        """The frame's camera continues the chain: the next frame is linked to it."""
        self.lost = False

    def carry(self) -> bool:
        """One more frame carried on the motion prior alone, if the chain may carry it (not lost, and fewer than
        ``max_motion_prior_frames`` in a row); returns whether it is carried."""
        if self.lost or self.carried >= self.config.max_motion_prior_frames:
            return False
        self.carried += 1
        return True

    def observed(self) -> None:
        """A frame with observations of its own: the frames carried in a row start over."""
        self.carried = 0

    def end(self) -> None:
        """The chain ends: the next frame is not linked to it but re-initialised, the bar back at the threshold."""
        self.lost, self.carried, self.continued, self.faint_look = True, 0, False, False
        self.frames_rated = self.frames_sure = 0
        self.trusted, self.trusted_since = False, None
        self.trust_at = self.config.confidence_threshold
