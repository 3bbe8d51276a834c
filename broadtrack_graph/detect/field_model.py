"""The shipped field model: where it lives, and its keypoints on a frame.

The package carries one learned field model (``broadtrack_graph/models/field_model.onnx`` and its
contract ``field_model.json``; how it was trained and where it fails: docs/MODEL.md). It is a
``field`` model (:mod:`broadtrack_graph.detect.onnx_contract`): 57 keypoint heatmaps in the NBJW
numbering and 27 line-class maps, at a quarter of its 512x288 input. :class:`FieldModel` runs it on
one frame with onnxruntime and returns its keypoints (one per class: the heatmap's peak above the
contract's threshold, sub-cell by a parabola), each with its pitch position.
"""

from __future__ import annotations

import time
from pathlib import Path

import numpy as np

from broadtrack_graph.detect.detector import Detections, check_image
from broadtrack_graph.detect.onnx_detector import OnnxDetector
from broadtrack_graph.errors import InputError
from broadtrack_graph.types.observations import KeypointObservations

SHIPPED_FIELD_MODEL = Path(__file__).resolve().parent.parent / "models" / "field_model.onnx"
"""The field model the package ships (its contract is the .json beside it)."""


def shipped_field_model() -> Path | None:
    """The shipped model's path, or None when this copy of the package has none."""
    return SHIPPED_FIELD_MODEL if SHIPPED_FIELD_MODEL.is_file() else None


class FieldModel:
    """A ``field`` model's keypoints (and, through :meth:`detect`, its lines) on a frame.

    Args:
        model_path: a field model's .onnx (default: the shipped one).
        threads: onnxruntime intra-op threads (1: the tracker's other work runs beside it).

    Raises:
        InputError: no model (none given and none shipped), or a model that breaks its contract.
    """

    def __init__(self, model_path: str | Path | None = None, threads: int = 1):
        path = model_path if model_path is not None else shipped_field_model()
        if path is None:
            raise InputError(SHIPPED_FIELD_MODEL, "no field model shipped with this copy of the package")
        self.detector = OnnxDetector(field_model=path, threads=threads)
        self.model = self.detector.models[0]
        self.path = Path(path)
        self.forward_ms: list[float] = []

    def keypoints(self, image_bgr: np.ndarray) -> KeypointObservations:
        """The model's keypoints on one (H, W, 3) uint8 BGR frame, in its pixels.

        Returns:
            KeypointObservations: uv_px (K, 2) pixels, points_w (K, 3) metres, confidence (K,) heatmap peaks,
            K <= 57 (nothing above the threshold: K = 0).

        Raises:
            InputError: the model's scores are not finite (a broken model), naming the model file.
        """
        image = check_image(image_bgr)
        started = time.perf_counter()
        scores = self.model.scores(image, only="keypoints")
        self.forward_ms.append(1000 * (time.perf_counter() - started))
        if not np.isfinite(scores["keypoints"]).all():
            raise InputError(self.path, "the model gave NaN or infinite keypoint scores")
        head = next(h for h in self.model.contract.outputs if h.name == "keypoints")
        return self.detector.decode_keypoints(scores["keypoints"], head, self.model.contract.threshold,
                                              (image.shape[1], image.shape[0]))

    def detect(self, image_bgr: np.ndarray) -> Detections:
        """Keypoints and named line points of one frame (the ``--detector onnx`` detections)."""
        return self.detector.detect(image_bgr)
