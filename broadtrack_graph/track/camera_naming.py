"""Which camera id a camera found for a frame belongs to (re-initialisation's naming step). No I/O.

A trusted chain's camera keeps its chain's id: a shot's camera does not change. Any other camera found (at a shot's
start, or while its chain is not trusted yet and its id is no more than a guess's) is named by where it stands
(:class:`~broadtrack_graph.track.camera_ids.CameraRegistry`: along and across its line of sight; a narrow view's
distance loosely, up to ``NARROW_ALONG_SIGHT_SHARE`` of it along). A confident one takes a known camera's id only when
the frame, refined with the focal point at that camera's position, is still explained within ``reinit_switch_margin``
of its confidence (a tripod: another stadium's camera at a similar place is not; a camera found on that tripod is
explained there already), else a new id; one that is not
confident takes the nearest known camera's. The refit starts from the camera moved there with its angles and focal
length kept, or, a narrow view's from further along its line of sight than the registry's gate, with its view kept
(:func:`~broadtrack_graph.geometry.aim.moved_keeping_view`).
"""

from __future__ import annotations

from broadtrack_graph.geometry.aim import moved_keeping_view
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.reinit.court_config import CourtConfig
from broadtrack_graph.reinit.scoring import ReinitResult
from broadtrack_graph.track.camera_ids import CameraRegistry
from broadtrack_graph.track.chain import Chain
from broadtrack_graph.track.config import TrackingConfig

NARROW_VIEW_FOCAL_PER_WIDTH = CourtConfig().narrow_view_focal_per_width
"""A view whose focal length is at least this many image widths (about 37 deg across or less) is narrow: nearly
affine, its distance along its line of sight and its focal length trade off."""
NARROW_ALONG_SIGHT_SHARE = 0.6
"""A narrow view's camera is tried as a known camera standing off along its line of sight by up to this share of its
distance to the ground it looks at (:meth:`~broadtrack_graph.track.camera_ids.CameraRegistry.identify`): the real dev
clips' views zoomed three times (``bench real --zoom 3``, 6.6-10 deg across) were placed up to 59 % of that distance
off along it (the clips' own cameras on their whole frames the truth), their focal lengths as far off, with every
marking drawn right."""


class CameraNaming:
    """The camera id of a camera found for a frame (module docstring).

    Args:
        config: ``confidence_threshold`` (a confident camera) and ``reinit_switch_margin`` (how well the frame must
            still be explained from a known camera's position).
        registry: the run's cameras by id, read and added to.
        chain: the run's chain, read for its camera id and its trust.
        refine: ``(guesses [(label, Camera)], detections, curves) -> ReinitResult``: the best guess after a local fit
            on the frame's marking map.
    """

    def __init__(self, config: TrackingConfig, registry: CameraRegistry, chain: Chain, refine) -> None:
        self.config, self.registry, self.chain, self.refine = config, registry, chain, refine

    def id_of(self, result: ReinitResult, confidence: float, frame) -> str | None:
        """A found camera's id: the trusted chain's, or by where it stands (a new id is provisional until trusted).

        Args:
            result: the camera found; confidence: its confidence on the frame.
            frame: (detections, curves, score) of the frame it was found on (``score``: camera -> its confidence).
        """
        if self.chain.camera_id is not None and self.chain.trusted:
            return self.chain.camera_id
        camera = result.camera
        if confidence >= self.config.confidence_threshold:
            # a narrow view is tried further along its line of sight only where the frame can tell (a marking map)
            narrow = camera.focal_px >= NARROW_VIEW_FOCAL_PER_WIDTH * camera.width_px and \
                getattr(frame[0], "marking_mask", None) is not None
            return self.registry.identify(camera.position_m, camera.R_cw[2], fits=lambda camera_id: self._fits_known(
                camera_id, camera, confidence, frame, narrow), along_share=NARROW_ALONG_SIGHT_SHARE if narrow else 0.0)
        return self.registry.nearest(camera.position_m, camera.R_cw[2])

    def _fits_known(self, camera_id: str, camera: Camera, confidence: float, frame, narrow: bool = False) -> bool:
        """Whether the frame's view, moved to the known camera's position and refined there, is still explained within
        the margin of ``confidence``: moved with its angles and focal length kept, or, a narrow view's from a known
        camera further along its line of sight than the registry's gate, with its view kept (its ground aim and image
        scale there: its angles and focal length kept, a fit would start tens of metres from where it is)."""
        detections, curves, score = frame
        if getattr(detections, "marking_mask", None) is None:
            return True  # labelled detections: where it stands decides
        if self.registry.on_tripod(camera_id, camera.position_m):
            return True  # found on the known camera's tripod (its search holds it there): explained from there already
        known = self.registry.positions[camera_id]
        far_along = narrow and not self.registry.stands_at(camera_id, camera.position_m, camera.R_cw[2])
        moved = (moved_keeping_view(camera, known) if far_along else None) or camera.replace(position_m=known)
        refined = self.refine([(f"at the position of {camera_id}", moved)], detections, curves)
        if refined.camera is None:
            return False
        fitted = refined.score.jaccard if refined.score is not None else score(refined.camera)
        return fitted is not None and fitted >= confidence - self.config.reinit_switch_margin
