"""Learned detectors run with onnxruntime: line segmentation and keypoint heatmaps.

The model contract lives in a small JSON file next to the model (``model.onnx`` ->
``model.json``) so that any network exported to it can be used (scripts/export_onnx.py
writes both):

.. code-block:: json

    {
      "kind": "lines",                       // or "keypoints"
      "input": {"width": 960, "height": 540, // network input size (the frame is resized to it)
                "colour_order": "RGB",       // or "BGR"
                "scale": 0.00392156862745098,// pixel value * scale, then (x - mean) / std per channel
                "mean": [0.485, 0.456, 0.406], "std": [0.229, 0.224, 0.225]},
      "output": {"activation": "softmax",    // softmax over channels | sigmoid per channel | none
                 "classes": ["background", "Big rect. left bottom", ...]},
      "threshold": 0.5                       // probability above which a pixel / peak counts
    }

* ``lines``: one output (1, C, h, w); channel c is the score of ``classes[c]``; a class
  called ``"background"`` (any case) is ignored. Each pixel takes its best channel; the
  pixels of a class above the threshold are mapped to frame pixels and thinned to
  centre-line points by mean shift (meanshift.mean_shift_thin), as in BroadTrack.
* ``keypoints``: one output (1, K, h, w) of heatmaps; ``classes`` are template keypoint
  names (PitchTemplate.keypoints) or "background"; each channel's maximum above the
  threshold, refined to sub-pixel by a parabola through its neighbours, is a keypoint.

Input/output sizes are read from the model; the JSON must agree. Mismatches raise
InputError naming the file. No other I/O than reading the model and its JSON.
"""

from __future__ import annotations

import time
from dataclasses import dataclass
from pathlib import Path

import cv2
import numpy as np

from broadtrack_graph.detect.detector import Detections, PredictedCamera, check_image
from broadtrack_graph.detect.meanshift import mean_shift_thin
from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.pitch import LINE_CLASSES, PitchTemplate
from broadtrack_graph.io.jsonfile import read_json
from broadtrack_graph.types.observations import KeypointObservations

KINDS = ("lines", "keypoints")
ACTIVATIONS = ("softmax", "sigmoid", "none")


@dataclass(frozen=True)
class ModelContract:
    """The metadata of one ONNX model (see module docstring)."""

    kind: str
    width_px: int
    height_px: int
    colour_order: str
    scale: float
    mean: tuple[float, float, float]
    std: tuple[float, float, float]
    activation: str
    classes: tuple[str, ...]
    threshold: float

    def to_json(self) -> dict:
        return {
            "kind": self.kind,
            "input": {"width": self.width_px, "height": self.height_px, "colour_order": self.colour_order,
                      "scale": self.scale, "mean": list(self.mean), "std": list(self.std)},
            "output": {"activation": self.activation, "classes": list(self.classes)},
            "threshold": self.threshold,
        }


def contract_path(model_path: str | Path) -> Path:
    """``model.onnx`` -> ``model.json``."""
    return Path(model_path).with_suffix(".json")


def read_contract(path: str | Path) -> ModelContract:
    """Read and validate a model's JSON contract (InputError naming the file on any problem)."""
    data = read_json(path)
    try:
        kind = data["kind"]
        inp, out = data["input"], data["output"]
        contract = ModelContract(
            kind=str(kind), width_px=int(inp["width"]), height_px=int(inp["height"]),
            colour_order=str(inp.get("colour_order", "RGB")).upper(), scale=float(inp.get("scale", 1 / 255)),
            mean=tuple(float(v) for v in inp.get("mean", (0.0, 0.0, 0.0))),
            std=tuple(float(v) for v in inp.get("std", (1.0, 1.0, 1.0))),
            activation=str(out.get("activation", "softmax")), classes=tuple(str(c) for c in out["classes"]),
            threshold=float(data.get("threshold", 0.5)),
        )
    except (KeyError, TypeError, ValueError) as exc:
        raise InputError(path, f"bad model contract: {exc!r}") from None
    unknown = set(data) - {"kind", "input", "output", "threshold"}
    if unknown:
        raise InputError(path, f"unknown key(s) in model contract: {sorted(unknown)}")
    if contract.kind not in KINDS:
        raise InputError(path, f"kind must be one of {KINDS}, got {contract.kind!r}")
    if contract.activation not in ACTIVATIONS:
        raise InputError(path, f"activation must be one of {ACTIVATIONS}, got {contract.activation!r}")
    if contract.colour_order not in ("RGB", "BGR"):
        raise InputError(path, f"colour_order must be RGB or BGR, got {contract.colour_order!r}")
    if len(contract.mean) != 3 or len(contract.std) != 3 or min(contract.std) <= 0:
        raise InputError(path, "mean and std need 3 values, std positive")
    if contract.width_px < 8 or contract.height_px < 8:
        raise InputError(path, f"input size too small: {contract.width_px}x{contract.height_px}")
    pitch = PitchTemplate()
    for name in contract.classes:
        if name.lower() == "background":
            continue
        if contract.kind == "lines" and name not in LINE_CLASSES:
            raise InputError(path, f"unknown line class {name!r}")
        if contract.kind == "keypoints" and name not in pitch.keypoints:
            raise InputError(path, f"unknown keypoint {name!r}")
    return contract


class OnnxModel:
    """One ONNX model and its contract, run with onnxruntime on the CPU.

    Args:
        model_path: the .onnx file; its contract is the .json next to it.
        threads: intra-op threads for onnxruntime.
    """

    def __init__(self, model_path: str | Path, threads: int = 1):
        import onnxruntime as ort

        self.path = Path(model_path)
        if not self.path.is_file():
            raise InputError(self.path, "model file not found")
        json_path = contract_path(self.path)
        if not json_path.is_file():
            raise InputError(json_path, "model contract (JSON next to the model) not found")
        self.contract = read_contract(json_path)
        options = ort.SessionOptions()
        options.intra_op_num_threads = threads
        try:
            self.session = ort.InferenceSession(str(self.path), options, providers=["CPUExecutionProvider"])
        except Exception as exc:  # onnxruntime raises its own exception types
            raise InputError(self.path, f"cannot load ONNX model: {exc}") from None
        inputs, outputs = self.session.get_inputs(), self.session.get_outputs()
        if len(inputs) != 1 or len(outputs) < 1:
            raise InputError(self.path, f"expected 1 input and >= 1 output, got {len(inputs)} and {len(outputs)}")
        self.input_name = inputs[0].name
        shape = inputs[0].shape
        c = self.contract
        if len(shape) != 4 or (isinstance(shape[1], int) and shape[1] != 3) or (
                isinstance(shape[2], int) and shape[2] != c.height_px) or (isinstance(shape[3], int) and shape[3] != c.width_px):
            raise InputError(self.path, f"input shape {shape} does not match the contract (1, 3, {c.height_px}, {c.width_px})")
        out_channels = outputs[0].shape[1] if len(outputs[0].shape) == 4 else None
        if isinstance(out_channels, int) and out_channels != len(c.classes):
            raise InputError(self.path, f"output has {out_channels} channels, contract lists {len(c.classes)} classes")
        self._mean = np.asarray(c.mean, np.float32).reshape(3, 1, 1)
        self._std = np.asarray(c.std, np.float32).reshape(3, 1, 1)

    def preprocess(self, image_bgr: np.ndarray) -> np.ndarray:
        """(H, W, 3) uint8 BGR -> (1, 3, h, w) float32 tensor as the contract says."""
        c = self.contract
        resized = cv2.resize(image_bgr, (c.width_px, c.height_px), interpolation=cv2.INTER_AREA)
        if c.colour_order == "RGB":
            resized = resized[:, :, ::-1]
        tensor = resized.transpose(2, 0, 1).astype(np.float32) * np.float32(c.scale)
        return ((tensor - self._mean) / self._std)[None]

    def scores(self, image_bgr: np.ndarray) -> np.ndarray:
        """(C, h, w) per-class probabilities (activation applied)."""
        raw = self.session.run(None, {self.input_name: self.preprocess(image_bgr)})[0]
        if raw.ndim != 4 or raw.shape[0] != 1 or raw.shape[1] != len(self.contract.classes):
            raise InputError(self.path, f"output shape {raw.shape} does not match {len(self.contract.classes)} classes")
        out = raw[0].astype(np.float32)
        if self.contract.activation == "softmax":
            out = np.exp(out - out.max(axis=0, keepdims=True))
            out /= out.sum(axis=0, keepdims=True)
        elif self.contract.activation == "sigmoid":
            out = 1.0 / (1.0 + np.exp(-out))
        return out


def _to_frame(points_net: np.ndarray, net_size: tuple[int, int], frame_size: tuple[int, int]) -> np.ndarray:
    """Network pixels -> frame pixels (pixel centres aligned)."""
    sx = frame_size[0] / net_size[0]
    sy = frame_size[1] / net_size[1]
    return np.column_stack([(points_net[:, 0] + 0.5) * sx - 0.5, (points_net[:, 1] + 0.5) * sy - 0.5])


class OnnxDetector:
    """Field markings from a line-segmentation model and/or a keypoint-heatmap model.

    Args:
        line_model: .onnx path of a ``lines`` model, or None.
        keypoint_model: .onnx path of a ``keypoints`` model, or None.
        bandwidth_px: mean-shift radius (frame pixels) for thinning class pixels.
        spacing_px: spacing of the thinned points (frame pixels).
    """

    def __init__(self, line_model=None, keypoint_model=None, bandwidth_px: float = 4.0, spacing_px: float = 6.0,
                 threads: int = 1, pitch: PitchTemplate | None = None):
        if line_model is None and keypoint_model is None:
            raise ValueError("OnnxDetector needs a line model, a keypoint model or both")
        self.lines = OnnxModel(line_model, threads) if line_model is not None else None
        self.keypoints = OnnxModel(keypoint_model, threads) if keypoint_model is not None else None
        for model, kind in ((self.lines, "lines"), (self.keypoints, "keypoints")):
            if model is not None and model.contract.kind != kind:
                raise InputError(contract_path(model.path), f"expected a '{kind}' model, contract says '{model.contract.kind}'")
        self.bandwidth_px, self.spacing_px = bandwidth_px, spacing_px
        self.pitch = pitch or PitchTemplate()

    def detect(self, image_bgr: np.ndarray, predicted: PredictedCamera | None = None) -> Detections:
        """Run the models on one (H, W, 3) uint8 BGR frame; ``predicted`` is not needed."""
        started = time.perf_counter()
        image = check_image(image_bgr)
        H, W = image.shape[:2]
        detections = Detections(width_px=W, height_px=H, marking_mask=np.zeros((H, W), dtype=bool))
        if self.lines is not None:
            self._detect_lines(image, detections)
        if self.keypoints is not None:
            detections.keypoints = self._detect_keypoints(image)
        detections.info["detect_ms"] = 1000 * (time.perf_counter() - started)
        return detections

    def _detect_lines(self, image: np.ndarray, detections: Detections) -> None:
        model = self.lines
        c = model.contract
        probs = model.scores(image)
        best = probs.argmax(axis=0)
        best_p = probs.max(axis=0)
        net_size, frame_size = (c.width_px, c.height_px), (detections.width_px, detections.height_px)
        marks = np.zeros((c.height_px, c.width_px), dtype=np.uint8)
        scale = np.sqrt(frame_size[0] / net_size[0] * frame_size[1] / net_size[1])
        all_points = []
        for channel, name in enumerate(c.classes):
            if name.lower() == "background":
                continue
            sel = (best == channel) & (best_p >= c.threshold)
            if not sel.any():
                continue
            marks |= sel.astype(np.uint8)
            ys, xs = np.nonzero(sel)
            pixels = _to_frame(np.column_stack([xs, ys]).astype(float), net_size, frame_size)
            points = mean_shift_thin(pixels, max(self.bandwidth_px, 2.5 * scale), max(self.spacing_px, 1.5 * scale),
                                     weights=best_p[ys, xs])
            detections.lines_px[name] = points
            all_points.append(points)
        detections.marking_points_px = np.vstack(all_points) if all_points else np.zeros((0, 2))
        detections.marking_mask = cv2.resize(marks * 255, frame_size, interpolation=cv2.INTER_NEAREST) > 0

    def _detect_keypoints(self, image: np.ndarray) -> KeypointObservations:
        model = self.keypoints
        c = model.contract
        heat = model.scores(image)
        uv, names, conf = [], [], []
        h, w = heat.shape[1:]
        for channel, name in enumerate(c.classes):
            if name.lower() == "background":
                continue
            m = heat[channel]
            flat = int(np.argmax(m))
            y, x = divmod(flat, w)
            peak = float(m[y, x])
            if peak < c.threshold:
                continue
            dx = dy = 0.0
            if 0 < x < w - 1:
                den = m[y, x - 1] - 2 * peak + m[y, x + 1]
                dx = 0.5 * (m[y, x - 1] - m[y, x + 1]) / den if den < 0 else 0.0
            if 0 < y < h - 1:
                den = m[y - 1, x] - 2 * peak + m[y + 1, x]
                dy = 0.5 * (m[y - 1, x] - m[y + 1, x]) / den if den < 0 else 0.0
            uv.append((x + dx, y + dy))
            names.append(name)
            conf.append(peak)
        H, W = image.shape[:2]
        uv_px = _to_frame(np.asarray(uv, float).reshape(-1, 2), (c.width_px, c.height_px), (W, H))
        return KeypointObservations(uv_px=uv_px, points_w=self.pitch.keypoint_array(names),
                                    confidence=np.asarray(conf, float), names=names)
