"""Learned detectors run with onnxruntime: line segmentation, keypoint heatmaps, or one field model with both.

The model contract lives in a small JSON file next to the model (``model.onnx`` -> ``model.json``,
:mod:`broadtrack_graph.detect.onnx_contract`), so that any network exported to it can be used
(scripts/export_onnx.py and scripts/train_field_model.py write both):

* ``lines``: one output (1, C, h, w); channel c is the score of ``classes[c]``; a class
  called ``"background"`` (any case) is ignored. Each cell takes its best channel; the
  cells of a class above the threshold are mapped to frame pixels and thinned to
  centre-line points by mean shift (meanshift.mean_shift_thin), as in BroadTrack.
* ``keypoints``: one output (1, K, h, w) of heatmaps; ``classes`` are template keypoint
  names, ``nbjw:<number>`` keypoints or "background"; each channel's maximum above the
  threshold, refined to sub-pixel by a parabola through its neighbours, is a keypoint.
* ``field``: one model with both outputs (``keypoints``, ``lines``), run once per frame.

The output grid may be coarser than the input (a stride): cell centres are mapped to frame
pixels by the grid's own size. Input/output sizes are read from the model; the JSON must
agree. Mismatches raise InputError naming the file. No other I/O than reading the model and its JSON.
"""

from __future__ import annotations

import time
from pathlib import Path

import cv2
import numpy as np

from broadtrack_graph.detect.detector import Detections, PredictedCamera, check_image
from broadtrack_graph.detect.meanshift import mean_shift_thin
from broadtrack_graph.detect.onnx_contract import (
    ModelContract,
    OutputContract,
    contract_path,
    keypoint_world_point,
    read_contract,
)
from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.types.observations import KeypointObservations

__all__ = ["ModelContract", "OnnxDetector", "OnnxModel", "contract_path", "read_contract"]

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
        wanted = len(self.contract.outputs)
        if len(inputs) != 1 or len(outputs) < wanted:
            raise InputError(self.path, f"expected 1 input and >= {wanted} output(s), got {len(inputs)} and {len(outputs)}")
        self.input_name = inputs[0].name
        shape = inputs[0].shape
        c = self.contract
        if len(shape) != 4 or (isinstance(shape[1], int) and shape[1] != 3) or (
                isinstance(shape[2], int) and shape[2] != c.height_px) or (isinstance(shape[3], int) and shape[3] != c.width_px):
            raise InputError(self.path, f"input shape {shape} does not match the contract (1, 3, {c.height_px}, {c.width_px})")
        for output, head in zip(outputs, c.outputs):
            out_channels = output.shape[1] if len(output.shape) == 4 else None
            if isinstance(out_channels, int) and out_channels != len(head.classes):
                raise InputError(self.path, f"output {head.name} has {out_channels} channels, contract lists "
                                            f"{len(head.classes)} classes")
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

    def scores(self, image_bgr: np.ndarray, only: str | None = None) -> dict[str, np.ndarray]:
        """Output name -> (C, h, w) per-class probabilities (each output's activation applied; only: that output)."""
        raws = self.session.run(None, {self.input_name: self.preprocess(image_bgr)})
        out = {}
        for raw, head in zip(raws, self.contract.outputs):
            if only is not None and head.name != only:
                continue
            if raw.ndim != 4 or raw.shape[0] != 1 or raw.shape[1] != len(head.classes):
                raise InputError(self.path, f"output {head.name} shape {raw.shape} does not match "
                                            f"{len(head.classes)} classes")
            probs = raw[0].astype(np.float32)
            if head.activation == "softmax":
                probs = np.exp(probs - probs.max(axis=0, keepdims=True))
                probs /= probs.sum(axis=0, keepdims=True)
            elif head.activation == "sigmoid":
                probs = 1.0 / (1.0 + np.exp(-probs))
            out[head.name] = probs
        return out


def _to_frame(points_net: np.ndarray, net_size: tuple[int, int], frame_size: tuple[int, int]) -> np.ndarray:
    """Output-grid cells (net_size = (w, h) of the grid) -> frame pixels (cell and pixel centres aligned)."""
    sx = frame_size[0] / net_size[0]
    sy = frame_size[1] / net_size[1]
    return np.column_stack([(points_net[:, 0] + 0.5) * sx - 0.5, (points_net[:, 1] + 0.5) * sy - 0.5])


class OnnxDetector:
    """Field markings from a line-segmentation model, a keypoint-heatmap model, or one field model with both.

    Args:
        line_model: .onnx path of a ``lines`` model, or None.
        keypoint_model: .onnx path of a ``keypoints`` model, or None.
        field_model: .onnx path of a ``field`` model (both outputs), or None; not with the other two.
        bandwidth_px: mean-shift radius (frame pixels) for thinning class pixels.
        spacing_px: spacing of the thinned points (frame pixels).
    """

    def __init__(self, line_model=None, keypoint_model=None, bandwidth_px: float = 4.0, spacing_px: float = 6.0,
                 threads: int = 1, pitch: PitchTemplate | None = None, field_model=None):
        if line_model is None and keypoint_model is None and field_model is None:
            raise ValueError("OnnxDetector needs a line model, a keypoint model, both, or a field model")
        if field_model is not None and (line_model is not None or keypoint_model is not None):
            raise ValueError("a field model holds both outputs: give it alone")
        self.models = [OnnxModel(path, threads) for path in (line_model, keypoint_model, field_model) if path is not None]
        for model, kind in zip(self.models, [k for k, path in (("lines", line_model), ("keypoints", keypoint_model),
                                                               ("field", field_model)) if path is not None]):
            if model.contract.kind != kind:
                raise InputError(contract_path(model.path), f"expected a '{kind}' model, contract says '{model.contract.kind}'")
        self.bandwidth_px, self.spacing_px = bandwidth_px, spacing_px
        self.pitch = pitch or PitchTemplate()

    def detect(self, image_bgr: np.ndarray, predicted: PredictedCamera | None = None) -> Detections:
        """Run the models on one (H, W, 3) uint8 BGR frame; ``predicted`` is not needed."""
        started = time.perf_counter()
        image = check_image(image_bgr)
        H, W = image.shape[:2]
        detections = Detections(width_px=W, height_px=H, marking_mask=np.zeros((H, W), dtype=bool))
        for model in self.models:
            scores = model.scores(image)
            for head in model.contract.outputs:
                if head.name == "lines":
                    self._lines(scores[head.name], head, model.contract.threshold, detections)
                else:
                    detections.keypoints = self.decode_keypoints(scores[head.name], head, model.contract.threshold, (W, H))
        detections.info["detect_ms"] = 1000 * (time.perf_counter() - started)
        return detections

    def _lines(self, probs: np.ndarray, head: OutputContract, threshold: float, detections: Detections) -> None:
        best = probs.argmax(axis=0)
        best_p = probs.max(axis=0)
        grid_size, frame_size = (probs.shape[2], probs.shape[1]), (detections.width_px, detections.height_px)
        marks = np.zeros(probs.shape[1:], dtype=np.uint8)
        scale = np.sqrt(frame_size[0] / grid_size[0] * frame_size[1] / grid_size[1])
        all_points = []
        for channel, name in enumerate(head.classes):
            if name.lower() == "background":
                continue
            sel = (best == channel) & (best_p >= threshold)
            if not sel.any():
                continue
            marks |= sel.astype(np.uint8)
            ys, xs = np.nonzero(sel)
            pixels = _to_frame(np.column_stack([xs, ys]).astype(float), grid_size, frame_size)
            points = mean_shift_thin(pixels, max(self.bandwidth_px, 2.5 * scale), max(self.spacing_px, 1.5 * scale),
                                     weights=best_p[ys, xs])
            detections.lines_px[name] = points
            all_points.append(points)
        detections.marking_points_px = np.vstack(all_points) if all_points else np.zeros((0, 2))
        detections.marking_mask = cv2.resize(marks * 255, frame_size, interpolation=cv2.INTER_NEAREST) > 0

    def decode_keypoints(self, heat: np.ndarray, head: OutputContract, threshold: float,
                         frame_size: tuple[int, int]) -> KeypointObservations:
        """(K, h, w) heatmaps -> keypoints in frame pixels: each class's peak above threshold, sub-cell by a parabola."""
        uv, names, points_w, conf = [], [], [], []
        h, w = heat.shape[1:]
        for channel, name in enumerate(head.classes):
            if name.lower() == "background":
                continue
            m = heat[channel]
            flat = int(np.argmax(m))
            y, x = divmod(flat, w)
            peak = float(m[y, x])
            if not peak >= threshold:  # NaN from a broken model counts as no keypoint
                continue
            dx = dy = 0.0
            if 0 < x < w - 1:
                den = m[y, x - 1] - 2 * peak + m[y, x + 1]
                dx = 0.5 * (m[y, x - 1] - m[y, x + 1]) / den if den < 0 else 0.0
            if 0 < y < h - 1:
                den = m[y - 1, x] - 2 * peak + m[y + 1, x]
                dy = 0.5 * (m[y - 1, x] - m[y + 1, x]) / den if den < 0 else 0.0
            uv.append((x + dx, y + dy))
            names.append(name if name in self.pitch.keypoints else "")  # an nbjw:<n> keypoint goes by its world point
            points_w.append(keypoint_world_point(name, self.pitch))
            conf.append(peak)
        uv_px = _to_frame(np.asarray(uv, float).reshape(-1, 2), (w, h), frame_size)
        return KeypointObservations(uv_px=uv_px, points_w=np.asarray(points_w, float).reshape(-1, 3),
                                    confidence=np.asarray(conf, float), names=names)
