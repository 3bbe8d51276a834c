"""The online tripod policy: a provisional tripod after a few confident frames, a fit after more.

Online without a known tripod, the solver first tracks without the tripod term; this
policy collects the confident cameras and sets the solver's tripod, then holds it fixed.
"""

from __future__ import annotations

import logging

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.tripod_fit import fit_tripod_for_run, provisional_tripod_for_run
from broadtrack_graph.track.camera_ids import CameraRegistry
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.tripod_check import rejected_fit, standing_provisional
from broadtrack_graph.types.shot import MAIN_CAMERA_ID

log = logging.getLogger(__name__)


class OnlineTripod:
    """Fits the tripod on the confident opening frames of an online run, then holds it fixed.

    Only frames at least ``tripod_fit_min_confidence`` confident enter the fit. After
    ``tripod_provisional_frames`` of them a provisional tripod (typical delta and lambda, held as firmly as those
    frames agree where the camera stands,
    :func:`~broadtrack_graph.graph.tripod_fit.provisional_tripod_for_run`) holds the focal point in place; after
    ``tripod_fit_frames`` the fit replaces it. A fit that is not a consistent tripod (it explains fewer than
    ``tripod_fit_min_inliers`` of its frames, or puts the tripod under 3 m, on the pitch or out of the stadium:
    :func:`~broadtrack_graph.track.tripod_check.rejected_fit`) is rejected: the older half of the frames is dropped
    and the fit is tried again once enough new ones have come.

    Args:
        config: tracking options (the ``tripod_*`` fields, ``use_tripod``, ``mode``).
        graph: solver settings (delta prior; lambda of the provisional tripod).
        pitch: the template (where a tripod may not be).
        known_tripod: a tripod given to the run; the policy then does nothing.
        known_tripods: tripods given per camera id (the shot step's ids); a camera with one is not fitted.

    One tripod per camera: when the shots switch to another camera (:meth:`switch`, told by the run's
    :class:`~broadtrack_graph.track.chain.Chain`, the one owner of the chain's camera id), the
    tripod fitted or given for the camera left is kept, and the one of the camera coming
    back is put in the solver (or a new fit starts for a camera seen the first time).

    Attributes:
        held_id: the camera id whose tripod the solver holds or is fitting (None: no identified camera's). Not the
            chain's camera id: after a cut the chain's camera is unknown while its tripod stays held, so a camera
            returning after a close-up keeps its tripod and the cameras collected for it.
        info: what the last provisional tripod or fit reported (written to the run summary
            and ``tripod.json``), or None.
        provisional: the solver's tripod is the provisional one (to be replaced by the fit).
        cameras: the confident cameras collected so far.
    """

    def __init__(self, config: TrackingConfig, graph: GraphConfig, pitch: PitchTemplate,
                 known_tripod: Tripod | None, known_tripods: dict[str, Tripod] | None = None) -> None:
        self.config = config
        self.tripods: dict[str, Tripod] = dict(known_tripods or {})  # camera id -> its tripod
        self.held_id: str | None = None
        self.graph = graph
        self.pitch = pitch
        self.known_tripod = known_tripod
        self.cameras: list[Camera] = []
        self.provisional = False
        self.info: dict | None = None

    def switch(self, solver, camera_id: str) -> None:
        """The shots moved to camera ``camera_id``: keep the tripod of the camera left, put this one's in the solver."""
        if camera_id == self.held_id:
            return
        if self.held_id is not None and solver.tripod is not None and not self.provisional:
            self.tripods[self.held_id] = solver.tripod
        if self.held_id is None and not self.tripods and self.known_tripod is not None:
            self.tripods[camera_id] = self.known_tripod  # a run given one tripod without camera ids: the first camera's
        self.held_id = camera_id
        tripod = self.tripods.get(camera_id)
        if tripod is not None or self.config.use_tripod:
            solver.tripod = tripod if self.config.use_tripod else None
        self.known_tripod = tripod
        self.provisional = False
        self.cameras = []

    def release(self, solver) -> None:
        """A camera not identified yet took over from camera ``held_id``: keep that camera's tripod, hold none in the
        solver (another camera's tripod would pull this one to where that camera stands)."""
        if self.held_id is None:
            return  # nothing identified yet: a tripod given to the run stays for the first camera
        if solver.tripod is not None and not self.provisional:
            self.tripods[self.held_id] = solver.tripod
        self.held_id, self.known_tripod, self.provisional, self.cameras = None, None, False, []
        solver.tripod = None

    def new_chain(self, solver, camera: Camera, registry: CameraRegistry) -> None:
        """A re-initialisation starts a chain that does not continue the last one at ``camera``: when it cannot stand
        where the cameras collected for this camera's tripod stand (``registry``'s rule, along and across its line of
        sight), those cameras, and the provisional tripod made from them, are dropped. They stood elsewhere (a wrong
        chain the re-initialisation replaced): held in the tripod factor, their tripod would pull every frame of the
        new chain off, and each would be re-initialised. A fitted or given tripod stays.
        """
        if self.known_tripod is not None or (solver.tripod is not None and not self.provisional):
            return
        tripod = solver.tripod if self.provisional else provisional_tripod_for_run(self.cameras, self.graph)
        if tripod is None or registry.same_place(tripod.T_w, camera.position_m, camera.R_cw[2]):
            return
        log.info("a new chain's camera stands %.1f m from the cameras collected for its tripod: they are dropped",
                 float(np.linalg.norm(np.subtract(camera.position_m, tripod.T_w))))
        self.cameras = []
        if self.provisional:
            solver.tripod, self.provisional, self.info = None, False, None

    def by_camera(self, solver) -> dict[str, Tripod]:
        """Every camera's tripod so far (fitted or given; the current camera's as the solver holds it)."""
        out = dict(self.tripods)
        if self.held_id is not None and solver.tripod is not None:
            out[self.held_id] = solver.tripod
        return out

    def write(self, solver, folder, summary: dict) -> tuple[Tripod | None, dict[str, Tripod]]:
        """At the end of a run: the tripod file (the main camera's tripod, else the last camera's, and every
        camera's) in the run folder and the summary's ``tripod`` / ``tripod_fit``; returns (that tripod, by id)."""
        by_camera = self.by_camera(solver)
        tripod = by_camera.get(MAIN_CAMERA_ID, solver.tripod)
        if tripod is not None:
            summary["tripod"] = {"T_w": list(map(float, tripod.T_w)), "delta_m": float(tripod.delta_m)}
            folder.write_tripod(tripod, self.info, by_camera)
        if self.info:
            summary["tripod_fit"] = self.info
        return tripod, by_camera

    def update(self, solver, camera: Camera | None, confidence: float | None) -> None:
        """Add one frame's camera (None: not trusted) and set ``solver.tripod`` when due.

        Args:
            solver: holds the tripod in use (a :class:`~broadtrack_graph.graph.streaming.StreamingSolver`
                or anything with a settable ``tripod``).
            camera: the frame's camera, or None when the frame is not trusted.
            confidence: its confidence in [0, 1], or None.
        """
        if not self.config.use_tripod or self.known_tripod is not None or self.config.mode == "batch":
            return
        if solver.tripod is not None and not self.provisional:
            return
        if camera is None or confidence is None or confidence < self.config.tripod_fit_min_confidence:
            return
        self.cameras.append(camera)
        settings = self.graph.solver
        if (solver.tripod is None and self.config.tripod_provisional_frames
                and len(self.cameras) >= self.config.tripod_provisional_frames):
            provisional = standing_provisional(self.cameras, self.graph, self.pitch)
            if provisional is not None:
                solver.tripod = provisional
                self.provisional = True
                self.info = {"provisional": True, "frames": len(self.cameras),
                             "reason": "typical delta and lambda; replaced once enough frames are fitted"}
                log.info("provisional tripod from %d frames: T=%s", len(self.cameras),
                         np.round(provisional.T_w, 2).tolist())
        if len(self.cameras) < self.config.tripod_fit_frames:
            return
        tripod, info = fit_tripod_for_run(self.cameras, settings)
        rejected = None if tripod is None else rejected_fit(tripod, info, self.config, self.pitch)
        if rejected is not None:
            info["rejected"] = rejected
            log.info("online tripod fit rejected: %s", rejected)
            tripod = None
        self.info = info
        if tripod is not None:
            solver.tripod = tripod
            self.provisional = False
            log.info("tripod fitted on %d frames: T=%s delta=%.3f m", len(self.cameras),
                     np.round(tripod.T_w, 2).tolist(), tripod.delta_m)
            self.cameras = []
        else:
            self.cameras = self.cameras[len(self.cameras) // 2:]
