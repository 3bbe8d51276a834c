#!/usr/bin/env python
"""Export a PyTorch / TorchScript field-marking network to the ONNX contract of broadtrack-graph.

Writes ``OUT.onnx`` and its contract ``OUT.json`` (see broadtrack_graph/detect/onnx_detector.py),
then loads both back with onnxruntime and checks the output shape. torch is needed here
only; the package never imports it.

Examples:

    # a TorchScript line-segmentation model (e.g. traced from a TVCalib-style network)
    python scripts/export_onnx.py --kind lines --torchscript seg.pt --width 960 --height 540 \\
        --classes background "Big rect. left bottom" ... --out models/lines.onnx

    # a Python module exposing a factory, plus a state dict (e.g. an NBJW-style keypoint network)
    python scripts/export_onnx.py --kind keypoints --factory mypkg.nets:build_hrnet --weights kp.pth \\
        --width 960 --height 540 --classes-file keypoint_names.txt --activation sigmoid --out models/kp.onnx

The network must take a (1, 3, H, W) float tensor prepared as the contract says
(colour order, scale, mean, std) and return (1, C, h, w) scores, channel c for classes[c].
"""

from __future__ import annotations

import argparse
import importlib
import sys
from pathlib import Path


def parse_args(argv=None):
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[1])
    parser.add_argument("--kind", choices=("lines", "keypoints"), required=True)
    source = parser.add_mutually_exclusive_group(required=True)
    source.add_argument("--torchscript", type=Path, help="a TorchScript file (torch.jit.save)")
    source.add_argument("--factory", help="module:function returning an nn.Module (with --weights)")
    parser.add_argument("--weights", type=Path, help="state dict for --factory")
    parser.add_argument("--width", type=int, required=True, help="network input width")
    parser.add_argument("--height", type=int, required=True, help="network input height")
    names = parser.add_mutually_exclusive_group(required=True)
    names.add_argument("--classes", nargs="+", help="output channel names in order ('background' allowed)")
    names.add_argument("--classes-file", type=Path, help="one output channel name per line")
    parser.add_argument("--colour-order", choices=("RGB", "BGR"), default="RGB")
    parser.add_argument("--scale", type=float, default=1 / 255)
    parser.add_argument("--mean", type=float, nargs=3, default=(0.485, 0.456, 0.406))
    parser.add_argument("--std", type=float, nargs=3, default=(0.229, 0.224, 0.225))
    parser.add_argument("--activation", choices=("softmax", "sigmoid", "none"), default="softmax")
    parser.add_argument("--threshold", type=float, default=0.5)
    parser.add_argument("--opset", type=int, default=17)
    parser.add_argument("--out", type=Path, required=True, help="output .onnx path (the .json goes next to it)")
    return parser.parse_args(argv)


def load_model(args):
    import torch

    if args.torchscript is not None:
        return torch.jit.load(str(args.torchscript), map_location="cpu")
    module_name, _, function = args.factory.partition(":")
    model = getattr(importlib.import_module(module_name), function)()
    if args.weights is not None:
        state = torch.load(str(args.weights), map_location="cpu")
        model.load_state_dict(state.get("state_dict", state) if isinstance(state, dict) else state)
    return model


def main(argv=None) -> int:
    import json

    args = parse_args(argv)
    try:
        import torch
    except ImportError:
        raise SystemExit("this script needs PyTorch (pip install torch); the package itself does not") from None

    from broadtrack_graph.detect.onnx_detector import ModelContract, OnnxModel, contract_path, read_contract

    classes = args.classes or [line.strip() for line in args.classes_file.read_text().splitlines() if line.strip()]
    contract = ModelContract(args.kind, args.width, args.height, args.colour_order, args.scale, tuple(args.mean),
                             tuple(args.std), args.activation, tuple(classes), args.threshold)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    json_path = contract_path(args.out)
    json_path.write_text(json.dumps(contract.to_json(), indent=2))
    read_contract(json_path)  # validates class names against the template
    model = load_model(args).eval()
    dummy = torch.zeros(1, 3, args.height, args.width)
    with torch.no_grad():
        output = model(dummy)
        if isinstance(output, (tuple, list)):
            raise SystemExit("the network returns several outputs; wrap it to return the (1, C, h, w) scores only")
        if output.ndim != 4 or output.shape[1] != len(classes):
            raise SystemExit(f"output shape {tuple(output.shape)} does not match {len(classes)} classes")
        torch.onnx.export(model, dummy, str(args.out), input_names=["image"], output_names=["scores"],
                          opset_version=args.opset)
    OnnxModel(args.out)  # loads with onnxruntime and checks the contract against the graph
    print(f"wrote {args.out} and {json_path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
