"""One frame -> a camera without a trusted prediction, and the confidence of a camera for a frame."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from broadtrack_graph.detect.detector import Detections
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves, TemplateSampling
from broadtrack_graph.geometry.tripod import image_motion_vector
from broadtrack_graph.reinit.confidence import camera_confidence, recall_across_motion
from broadtrack_graph.reinit.keypoints import reinit_from_keypoints
from broadtrack_graph.reinit.lines import reinit_from_lines
from broadtrack_graph.reinit.mask import reinit_from_mask
from broadtrack_graph.reinit.mask_config import MaskSearchConfig
from broadtrack_graph.reinit.scoring import ReinitResult, score_labelled
from broadtrack_graph.types.observations import FrameObservations


def reinitialise(
    observations: FrameObservations,
    detections: Detections | None,
    pitch: PitchTemplate,
    positions_w=None,
    curves: TemplateCurves | None = None,
    sampling: TemplateSampling | None = None,
) -> ReinitResult:
    """A camera for a frame without a trusted prediction.

    Tries, by what the frame carries: labelled keypoints (two-point method in RANSAC),
    labelled lines (homography or global search), and the unlabelled marking map
    (line-pair and circle hypotheses at the candidate positions, scored and fitted).
    Cameras under 3 m, over the pitch or out of the stadium are dropped; the best score is kept.
    """
    W, H = observations.width_px, observations.height_px
    results = []
    kp = observations.keypoints
    if kp is not None and len(kp) >= 2:
        results.append(reinit_from_keypoints(kp.uv_px, kp.points_w, W, H, positions_w=positions_w))
    if observations.lines_px and sum(len(p) for p in observations.lines_px.values()) >= 6:
        results.append(reinit_from_lines(observations.lines_px, W, H, pitch, positions_w=positions_w, curves=curves,
                                         sampling=sampling))
    if detections is not None and detections.marking_mask is not None and not observations.lines_px:
        results.append(reinit_from_mask(detections.marking_mask, detections.marking_points_px, (W, H), pitch=pitch,
                                        positions_w=positions_w, curves=curves, field_mask=detections.field_mask,
                                        config=MaskSearchConfig()))
    good = [replace(r, camera=_wrapped(r.camera)) for r in results
            if r.camera is not None and plausible_position(r.camera.position_m, pitch)]
    if not good and any(r.camera is not None for r in results):
        return ReinitResult(None, None, "", f"every re-initialised camera was under {MIN_CAMERA_HEIGHT_M:g} m, on "
                                            "the pitch or out of the stadium")
    if not good:
        reasons = "; ".join(r.reason for r in results if r.reason) or "nothing to re-initialise from"
        return ReinitResult(None, None, "", reasons)
    return max(good, key=lambda r: (r.score.jaccard if r.score else 0.0, r.score.inlier_share if r.score else 0.0))


MAX_CAMERA_DISTANCE_M = 150.0
"""A broadcast camera stands in its stadium: its focal point within this horizontal distance of the centre spot.
Broadcast cameras stand within about 100 m of it (the top tier behind a goal of a large bowl); a camera fitted
farther has slid back along a narrow view's line of sight, where the focal length and the distance trade almost
freely and the image alone hardly tells them apart."""


MIN_CAMERA_HEIGHT_M = 3.0
"""A broadcast camera's focal point stands at least this high above the grass: of 1417 cameras a published
calibrator fitted to SoccerNet's test frames, 1412 stand 5 m or more up and 2 under 3 m (one of them under the grass).
Fitted lower, a camera sees the markings at a grazing angle, where grass texture lines up into faint runs that a
wrong camera explains (docs/BENCHMARKS.md, Why the defaults)."""


def plausible_position(position_w, pitch: PitchTemplate, min_height_m: float = MIN_CAMERA_HEIGHT_M,
                       max_distance_m: float = MAX_CAMERA_DISTANCE_M) -> bool:
    """A broadcast focal point or tripod: at least min_height_m above the grass, off the pitch and within
    max_distance_m (horizontally) of the centre spot.

    Args:
        position_w: (3,) metres, pitch frame (z down).
    """
    x, y, z = (float(v) for v in position_w)
    half_length, half_width = pitch.dimensions.length_m / 2, pitch.dimensions.width_m / 2
    return z <= -min_height_m and not (abs(x) < half_length and abs(y) < half_width) and \
        math.hypot(x, y) <= max_distance_m


def _wrapped(camera: Camera) -> Camera:
    """The same camera with pan and roll in (-pi, pi]."""
    pan = math.remainder(camera.pan_rad, 2 * math.pi)
    roll = math.remainder(camera.roll_rad, 2 * math.pi)
    return camera if (pan, roll) == (camera.pan_rad, camera.roll_rad) else camera.replace(pan_rad=pan, roll_rad=roll)


def frame_recall_across_motion(camera: Camera, previous: Camera, detections: Detections | None,
                               curves: TemplateCurves) -> float | None:
    """The recall of the template crossing the image's motion from ``previous`` to ``camera``
    (:func:`~broadtrack_graph.reinit.confidence.recall_across_motion`) on the frame's marking map; None without one
    (labelled lines or keypoints: not measured)."""
    if detections is None or detections.marking_mask is None or not detections.marking_mask.any():
        return None
    motion = image_motion_vector(previous, camera)
    return recall_across_motion(camera, detections.marking_mask, motion, curves, field_mask=detections.field_mask,
                                player_mask=detections.player_mask)[0]


def frame_confidence(
    camera: Camera,
    observations: FrameObservations,
    detections: Detections | None,
    curves: TemplateCurves,
    sampling: TemplateSampling,
) -> float | None:
    """Confidence in [0, 1] of a camera for a frame.

    By what the frame carries: the marking map (confidence.camera_confidence), else labelled lines
    (mean of the per-class Jaccard and the inlier share at 5 px), else keypoints (share within 10 px).
    A camera whose focal point is not a broadcast camera's (under 3 m, over the pitch or out of the stadium:
    :func:`plausible_position`) has confidence 0, however well it explains the markings.
    """
    if not plausible_position(camera.position_m, curves.pitch):
        return 0.0
    if detections is not None and detections.marking_mask is not None and detections.marking_mask.any():
        return camera_confidence(camera, detections.marking_mask, curves, field_mask=detections.field_mask,
                                 player_mask=detections.player_mask, motion_blur=detections.motion_blur)
    if observations.lines_px:
        score = score_labelled(camera, observations.lines_px, 5.0, sampling)
        return 0.5 * (score.jaccard + score.inlier_share)
    kp = observations.keypoints
    if kp is not None and len(kp):
        uv, front = camera.project(kp.points_w)
        error = np.linalg.norm(uv - kp.uv_px, axis=1)
        return float(np.mean(front & (error < 10.0)))
    return None
