#!/usr/bin/env python
"""Train the learned field model from our own renders, in one seeded command (torch: the ``train`` extra).

    python scripts/train_field_model.py --out runs/field_model --samples 20000 --hours 2.5

Steps, each resumable (run the same command again after a kill):

1. ``generate``: training shards of ``synth.field_samples.sample_field`` (seed ``TRAIN_SEED``) and held-out
   shards (seed ``HELD_OUT_SEED``, never trained on) into ``OUT/shards`` and ``OUT/shards-heldout``;
2. ``train``: the network on the training shards, checkpoints in ``OUT/checkpoint.pt``, losses in ``OUT/log.jsonl``;
3. ``export``: ``OUT/field_model.onnx`` and its contract ``OUT/field_model.json``, checked with onnxruntime.
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from field_model.shards import HELD_OUT_SEED, TRAIN_SEED, generate  # noqa: E402


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True)
    parser.add_argument("--steps", nargs="+", choices=("generate", "train", "export"),
                        default=["generate", "train", "export"])
    parser.add_argument("--samples", type=int, default=20000, help="training samples (default 20000)")
    parser.add_argument("--held-out", type=int, default=500, help="held-out samples (default 500)")
    parser.add_argument("--width", type=int, default=512, help="sample and network input width (default 512)")
    parser.add_argument("--height", type=int, default=288, help="sample and network input height (default 288)")
    parser.add_argument("--train-steps", type=int, default=20000)
    parser.add_argument("--batch", type=int, default=12)
    parser.add_argument("--hours", type=float, default=2.5, help="stop training after this long (resumable)")
    parser.add_argument("--workers", type=int, default=2, help="processes generating shards (default 2)")
    parser.add_argument("--threshold", type=float, default=0.3,
                        help="keypoint and line score threshold written into the contract (default 0.3)")
    parser.add_argument("--no-progress", action="store_true")
    args = parser.parse_args(argv)
    progress = not args.no_progress
    if "generate" in args.steps:
        generate(args.out / "shards-heldout", HELD_OUT_SEED, args.held_out, args.width, args.height, args.workers, progress)
        generate(args.out / "shards", TRAIN_SEED, args.samples, args.width, args.height, args.workers, progress)
    if "train" in args.steps:
        from field_model.train import TrainConfig, train

        train(TrainConfig(shards=str(args.out / "shards"), out=str(args.out), steps=args.train_steps,
                          batch=args.batch, hours=args.hours), progress=progress)
    if "export" in args.steps:
        from field_model.export import export

        path = export(args.out / "checkpoint.pt", args.out / "field_model.onnx", args.width, args.height,
                      args.threshold)
        print(f"exported {path} and {path.with_suffix('.json')}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
