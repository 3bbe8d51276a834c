"""One frame -> a camera from the learned field model alone: its keypoints through the keypoint path.

The model (:class:`~broadtrack_graph.detect.field_model.FieldModel`) gives up to 57 keypoints with
their pitch positions; :func:`~broadtrack_graph.reinit.keypoints.camera_from_keypoints` turns them
into a full camera (f, pan, tilt, roll, focal point; k1 0) wherever the camera stands. Tens of
milliseconds, against the global search's 0.3-2 s: the tracker tries it before the search, and
``calibrate --images`` uses it alone. No I/O (the model is loaded by the detect layer).
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from broadtrack_graph.detect.field_model import FieldModel, shipped_field_model
from broadtrack_graph.reinit.keypoints import camera_from_keypoints
from broadtrack_graph.reinit.scoring import ReinitResult

SHIPPED = "shipped"
"""``TrackingConfig.reinit_model`` value: the model shipped in the package."""

NO_MODEL = "none"
"""``TrackingConfig.reinit_model`` value: no model; the global search alone."""


@dataclass(frozen=True)
class ModelAcceptance:
    """When a camera from the model alone is trusted with nothing else to check it (``calibrate --images``).

    min_keypoints: keypoints the model must find (4 always fit a homography).
    min_inliers: of them, within the inlier distance of the camera (1 % of the width).
    min_inlier_share: and at least this share of them.
    """

    min_keypoints: int = 6
    min_inliers: int = 6
    min_inlier_share: float = 0.8

    def accepts(self, result: ReinitResult) -> bool:
        return (result.camera is not None and result.score is not None and result.score.tp >= self.min_inliers
                and result.score.inlier_share >= self.min_inlier_share)


class ModelReinit:
    """``image -> ReinitResult``: a camera from the field model's keypoints (module docstring).

    Args:
        model: the field model.
        min_keypoints: fewer keypoints give no camera (the reason says how many were found).
        positions_w: candidate focal points for fewer than 4 keypoints on the grass (default: the
            broadcast positions).
    """

    def __init__(self, model: FieldModel, min_keypoints: int = 4, positions_w=None):
        self.model = model
        self.min_keypoints = int(min_keypoints)
        self.positions_w = positions_w
        self.seconds = 0.0
        self.last_keypoints = None  # the keypoints of the last frame (KeypointObservations)

    def __call__(self, image_bgr: np.ndarray) -> ReinitResult:
        started = time.perf_counter()
        try:
            keypoints = self.last_keypoints = self.model.keypoints(image_bgr)
            H, W = image_bgr.shape[:2]
            if len(keypoints) < self.min_keypoints:
                return ReinitResult(None, None, "", f"field model: {len(keypoints)} keypoints (fewer than "
                                                    f"{self.min_keypoints})")
            result = camera_from_keypoints(keypoints.uv_px, keypoints.points_w, W, H, positions_w=self.positions_w)
            if result.camera is None:
                return result
            return ReinitResult(result.camera, result.score, f"field model ({len(keypoints)} keypoints, "
                                                             f"{result.hypothesis})", tried=len(keypoints))
        finally:
            self.seconds += time.perf_counter() - started


def model_reinit_for(choice: str | Path | None, threads: int = 1) -> ModelReinit | None:
    """The model re-initialisation a run asked for: :data:`SHIPPED` (None when the package ships no model),
    :data:`NO_MODEL` or None (none), or a field model's .onnx path.

    Raises:
        InputError: a path that is not a field model honouring its contract (naming the file).
    """
    if choice is None or str(choice) == NO_MODEL:
        return None
    if str(choice) == SHIPPED:
        path = shipped_field_model()
        return None if path is None else ModelReinit(FieldModel(path, threads))
    return ModelReinit(FieldModel(Path(choice), threads))
