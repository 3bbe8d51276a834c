"""The contract of a learned detector: the JSON file next to its ONNX model (``model.onnx`` -> ``model.json``).

Three kinds (the model's output is at the input size, or for ``field`` at any stride)::

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

    {
      "kind": "field",                       // one model, two outputs named "keypoints" and "lines"
      "input": {...},
      "outputs": {"keypoints": {"activation": "sigmoid", "classes": ["nbjw:1", ..., "nbjw:57"]},
                  "lines": {"activation": "softmax", "classes": ["background", "Big rect. left bottom", ...]}},
      "threshold": 0.3
    }

Line classes are SoccerNet's (``geometry.pitch.LINE_CLASSES``); keypoint classes are template keypoint
names (``PitchTemplate.keypoints``) or ``nbjw:<number>``, a keypoint of the 57-point numbering of
:data:`broadtrack_graph.io.nbjw_keypoints.NBJW_KEYPOINTS_W`; ``background`` (any case) is ignored.
Reading checks everything and raises InputError naming the file. No other I/O than reading the JSON.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from broadtrack_graph.errors import InputError
from broadtrack_graph.geometry.pitch import LINE_CLASSES, PitchTemplate
from broadtrack_graph.io.jsonfile import read_json
from broadtrack_graph.io.nbjw_keypoints import NBJW_KEYPOINTS_W

KINDS = ("lines", "keypoints", "field")
ACTIVATIONS = ("softmax", "sigmoid", "none")
FIELD_OUTPUTS = ("keypoints", "lines")
"""The outputs of a ``field`` model, by name, in this order."""

_NBJW = re.compile(r"nbjw:(\d+)$")


@dataclass(frozen=True)
class OutputContract:
    """One output of a model: what its channels are and how to turn them into probabilities."""

    name: str  # "lines" or "keypoints"
    activation: str
    classes: tuple[str, ...]


@dataclass(frozen=True)
class ModelContract:
    """The metadata of one ONNX model (see module docstring).

    activation, classes: the single output of a ``lines`` or ``keypoints`` model; ``heads``: the outputs
    of a ``field`` model (:data:`FIELD_OUTPUTS`).
    """

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
    heads: tuple[OutputContract, ...] = ()

    @property
    def outputs(self) -> tuple[OutputContract, ...]:
        """The model's outputs in the order of its ONNX outputs."""
        return self.heads if self.kind == "field" else (OutputContract(self.kind, self.activation, self.classes),)

    def to_json(self) -> dict:
        data = {
            "kind": self.kind,
            "input": {"width": self.width_px, "height": self.height_px, "colour_order": self.colour_order,
                      "scale": self.scale, "mean": list(self.mean), "std": list(self.std)},
        }
        if self.kind == "field":
            data["outputs"] = {h.name: {"activation": h.activation, "classes": list(h.classes)} for h in self.heads}
        else:
            data["output"] = {"activation": self.activation, "classes": list(self.classes)}
        data["threshold"] = self.threshold
        return data


def contract_path(model_path: str | Path) -> Path:
    """``model.onnx`` -> ``model.json``."""
    return Path(model_path).with_suffix(".json")


def keypoint_world_point(name: str, pitch: PitchTemplate) -> np.ndarray | None:
    """(3,) metres of a keypoint class (a template name or ``nbjw:<number>``), or None when unknown."""
    match = _NBJW.match(name)
    if match is not None:
        point = NBJW_KEYPOINTS_W.get(int(match.group(1)))
        return None if point is None else np.asarray(point, float)
    return np.asarray(pitch.keypoints[name], float) if name in pitch.keypoints else None


def _output(path, name: str, data: dict) -> OutputContract:
    head = OutputContract(name, str(data.get("activation", "softmax")), tuple(str(c) for c in data["classes"]))
    if head.activation not in ACTIVATIONS:
        raise InputError(path, f"activation must be one of {ACTIVATIONS}, got {head.activation!r}")
    pitch = PitchTemplate()
    for cls in head.classes:
        if cls.lower() == "background":
            continue
        if name == "lines" and cls not in LINE_CLASSES:
            raise InputError(path, f"unknown line class {cls!r}")
        if name == "keypoints" and keypoint_world_point(cls, pitch) is None:
            raise InputError(path, f"unknown keypoint {cls!r}")
    return head


def read_contract(path: str | Path) -> ModelContract:
    """Read and validate a model's JSON contract (InputError naming the file on any problem)."""
    data = read_json(path)
    if not isinstance(data, dict):
        raise InputError(path, "model contract must be a JSON object")
    unknown = set(data) - {"kind", "input", "output", "outputs", "threshold"}
    if unknown:
        raise InputError(path, f"unknown key(s) in model contract: {sorted(unknown)}")
    kind = data.get("kind")
    if kind not in KINDS:
        raise InputError(path, f"kind must be one of {KINDS}, got {kind!r}")
    try:
        inp = data["input"]
        if kind == "field":
            outputs = data["outputs"]
            if sorted(outputs) != sorted(FIELD_OUTPUTS):
                raise InputError(path, f"a field model's outputs must be {FIELD_OUTPUTS}, got {sorted(outputs)}")
            heads = tuple(_output(path, name, outputs[name]) for name in FIELD_OUTPUTS)
            single = heads[0]
        else:
            heads = ()
            single = _output(path, kind, data["output"])
        contract = ModelContract(
            kind=str(kind), width_px=int(inp["width"]), height_px=int(inp["height"]),
            colour_order=str(inp.get("colour_order", "RGB")).upper(), scale=float(inp.get("scale", 1 / 255)),
            mean=tuple(float(v) for v in inp.get("mean", (0.0, 0.0, 0.0))),
            std=tuple(float(v) for v in inp.get("std", (1.0, 1.0, 1.0))),
            activation=single.activation, classes=single.classes, threshold=float(data.get("threshold", 0.5)),
            heads=heads,
        )
    except InputError:
        raise
    except (KeyError, TypeError, ValueError, AttributeError) as exc:
        raise InputError(path, f"bad model contract: {exc!r}") from None
    if contract.colour_order not in ("RGB", "BGR"):
        raise InputError(path, f"colour_order must be RGB or BGR, got {contract.colour_order!r}")
    if len(contract.mean) != 3 or len(contract.std) != 3 or min(contract.std) <= 0:
        raise InputError(path, "mean and std need 3 values, std positive")
    if contract.width_px < 8 or contract.height_px < 8:
        raise InputError(path, f"input size too small: {contract.width_px}x{contract.height_px}")
    return contract
