#!/usr/bin/env python
"""Seconds per field-model training sample (broadtrack_graph.synth.field_samples) on one core.

Builds the textures of every texture seed first (once per process; not counted), then times
``sample_field`` over a run of indices at the requested size with OpenCV on one thread. Run it
pinned to one core for a clean figure:

    taskset -c 0 python scripts/time_field_samples.py --count 60 --width 960 --height 540

Prints the mean, median and 90th percentile, per kind, and with --profile the top of a cProfile.
"""

from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import statistics
import time

os.environ.setdefault("OMP_NUM_THREADS", "1")
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import cv2  # noqa: E402

from broadtrack_graph.synth.field_config import SampleConfig  # noqa: E402
from broadtrack_graph.synth.field_samples import field_textures, sample_field  # noqa: E402


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--count", type=int, default=60, help="samples to time")
    parser.add_argument("--width", type=int, default=960)
    parser.add_argument("--height", type=int, default=540)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--plain", action="store_true", help="every randomisation off (SampleConfig.plain())")
    parser.add_argument("--profile", action="store_true", help="print the top of a cProfile of the run")
    args = parser.parse_args(argv)
    cv2.setNumThreads(1)
    config = SampleConfig.plain() if args.plain else SampleConfig()
    for seed in range(config.texture_variants):
        field_textures(seed)
    sample_field(args.seed, 10_000, args.width, args.height, config)  # warm-up: caches of curves and fields
    profiler = cProfile.Profile() if args.profile else None
    seconds, kinds = [], {}
    for index in range(args.count):
        if profiler:
            profiler.enable()
        start = time.perf_counter()
        sample = sample_field(args.seed, index, args.width, args.height, config)
        elapsed = time.perf_counter() - start
        if profiler:
            profiler.disable()
        seconds.append(elapsed)
        kinds.setdefault(sample.kind, []).append(elapsed)
    ordered = sorted(seconds)
    print(f"{args.count} samples at {args.width}x{args.height}, one thread: mean {statistics.mean(seconds):.3f} s, "
          f"median {statistics.median(seconds):.3f} s, p90 {ordered[int(0.9 * (len(ordered) - 1))]:.3f} s per sample")
    for kind, values in sorted(kinds.items()):
        print(f"  {kind:12s} {len(values):3d} samples, mean {statistics.mean(values):.3f} s")
    if profiler:
        pstats.Stats(profiler).sort_stats("cumulative").print_stats(30)


if __name__ == "__main__":
    main()
