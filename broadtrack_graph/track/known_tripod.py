"""A known camera's tripod in re-initialisation: a camera's markings may fix it only there. No I/O.

With its focal point known a camera has 4 unknowns (f and three angles, :data:`~broadtrack_graph.geometry.determinable.
TRIPOD_CAMERA_UNKNOWNS`) instead of 7: a zoomed view of a circle's arc and a touchline (5 constraints) fixes a known
camera standing on its tripod, not a camera from nothing. Two rules of
:class:`~broadtrack_graph.track.reinit_policy.ReinitPolicy` read it:

- :func:`fixed_on_known_tripod`, the first camera's gate on a tripod: a camera standing on its trusted camera id's
  tripod (:meth:`~broadtrack_graph.track.camera_ids.CameraRegistry.on_tripod`) is kept when the markings it explains
  fix it there as surely as the court model's camera from nothing must be fixed: with a constraint to spare at
  ``court_accept_confidence``, exactly at :data:`EXACT_FIT_CONFIDENCE` (a tripod fitted on narrow views stands
  loosely along their line of sight, and a camera just over the threshold held there drifts).
- :func:`onto_its_tripod`: a searched camera at a known camera's place but off its tripod (the search frees the focal
  point near its candidates, and a narrow view slides along its line of sight), whose markings do not fix it from
  nothing, refitted with its focal point held on the tripod and its view kept
  (:func:`~broadtrack_graph.geometry.aim.moved_keeping_view`), taken when the frame is still explained within the
  margin.
"""

from __future__ import annotations

from dataclasses import replace

from broadtrack_graph.geometry.aim import moved_keeping_view
from broadtrack_graph.geometry.determinable import (
    TRIPOD_CAMERA_UNKNOWNS,
    Determinability,
    determinability,
    fixes_camera,
)
from broadtrack_graph.reinit.court_config import CourtConfig
from broadtrack_graph.reinit.scoring import ReinitResult
from broadtrack_graph.track.camera_ids import CameraRegistry
from broadtrack_graph.track.config import TrackingConfig

EXACT_FIT_CONFIDENCE = CourtConfig().exact_fit_confidence
"""A camera its markings fix exactly, with no constraint to spare, is taken from this confidence (the court model's
bar for its exact fits: laid on them, a wrong camera explains them as well)."""


def fixed_on_known_tripod(registry: CameraRegistry, config: TrackingConfig, camera_id: str | None, camera,
                          confidence: float, fixed: Determinability) -> bool:
    """Whether ``camera`` (of ``camera_id``, at ``confidence``) stands on its trusted camera id's tripod and the
    markings it explains (``fixed``) fix its focal length and angles there at the court model's bars (module
    docstring)."""
    if camera_id is None or camera_id in registry.untrusted or not registry.on_tripod(camera_id, camera.position_m):
        return False
    if fixes_camera(fixed, surplus=1, unknowns=TRIPOD_CAMERA_UNKNOWNS):
        return confidence >= config.court_accept_confidence
    return fixes_camera(fixed, unknowns=TRIPOD_CAMERA_UNKNOWNS) and confidence >= EXACT_FIT_CONFIDENCE


def onto_its_tripod(registry: CameraRegistry, config: TrackingConfig, refine, found: ReinitResult, confidence: float,
                    detections, pitch, curves, score) -> tuple[ReinitResult, float]:
    """A searched camera (``found`` at ``confidence``) refitted on a known camera's tripod, or itself (module
    docstring).

    Args:
        refine: ``(guesses [(label, Camera)], detections, curves, hold_position) -> ReinitResult``.
        detections: the frame's (its marking map); pitch, curves: the template.
        score: camera -> its confidence on the frame, when the refit gives none.
    """
    mask = getattr(detections, "marking_mask", None)
    camera = found.camera
    camera_id = registry.nearest(camera.position_m, camera.R_cw[2]) if mask is not None else None
    if camera_id is None or pitch is None or camera_id in registry.untrusted \
            or registry.on_tripod(camera_id, camera.position_m) \
            or fixes_camera(determinability(camera, pitch, explained_by=mask)):
        return found, confidence
    tripod = registry.positions[camera_id]
    start = moved_keeping_view(camera, tripod) or camera.replace(position_m=tripod)
    held = refine([(f"on the tripod of {camera_id}", start)], detections, curves, hold_position=True)
    if held.camera is None:
        return found, confidence
    held_confidence = held.score.jaccard if held.score is not None else score(held.camera)
    if held_confidence is None or held_confidence < confidence - config.reinit_switch_margin:
        return found, confidence
    return replace(found, camera=held.camera, hypothesis=held.hypothesis), float(held_confidence)
