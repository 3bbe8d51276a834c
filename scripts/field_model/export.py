"""The trained field network to ONNX, with its JSON contract (kind ``field``), checked with onnxruntime."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import torch

from field_model.network import KEYPOINTS, FieldNet
from field_model.train import MEAN, STD

LINE_CLASS_NAMES = None  # filled from the package on first use


def contract(width_px: int, height_px: int, threshold: float = 0.3) -> dict:
    """The ``field`` contract: input normalisation, the keypoint classes ``nbjw:1`` .. ``nbjw:57`` and the line classes."""
    from broadtrack_graph.geometry.pitch import LINE_CLASSES

    return {
        "kind": "field",
        "input": {"width": width_px, "height": height_px, "colour_order": "RGB", "scale": 1.0 / 255.0,
                  "mean": [float(v) for v in MEAN], "std": [float(v) for v in STD]},
        "outputs": {
            "keypoints": {"activation": "sigmoid", "classes": [f"nbjw:{k}" for k in range(1, KEYPOINTS + 1)]},
            "lines": {"activation": "softmax", "classes": ["background", *LINE_CLASSES]},
        },
        "threshold": threshold,
    }


def export(checkpoint: Path, out: Path, width_px: int, height_px: int, threshold: float = 0.3) -> Path:
    """Write ``out`` (.onnx) and ``out`` with .json from a checkpoint; load both back with onnxruntime and check shapes."""
    import onnxruntime as ort

    model = FieldNet()
    model.load_state_dict(torch.load(checkpoint, map_location="cpu")["model"])
    model.eval()
    dummy = torch.zeros(1, 3, height_px, width_px)
    out = Path(out)
    out.parent.mkdir(parents=True, exist_ok=True)
    torch.onnx.export(model, dummy, str(out), input_names=["image"], output_names=["keypoints", "lines"],
                      opset_version=17, dynamo=False)
    out.with_suffix(".json").write_text(json.dumps(contract(width_px, height_px, threshold), indent=1))
    session = ort.InferenceSession(str(out), providers=["CPUExecutionProvider"])
    keypoints, lines = session.run(None, {"image": dummy.numpy()})
    assert keypoints.shape == (1, KEYPOINTS, height_px // 4, width_px // 4), keypoints.shape
    assert lines.shape == (1, 27, height_px // 4, width_px // 4), lines.shape
    with torch.no_grad():
        ref_k, ref_l = model(dummy)
    assert np.allclose(ref_k.numpy(), keypoints, atol=1e-3) and np.allclose(ref_l.numpy(), lines, atol=1e-3)
    return out
