"""``broadtrack-graph bench speed``: frames per second of the whole pipeline and of each stage.

A synthetic clip is rendered once (1920x1080 by default; reused from ``--out`` when it is
there) and tracked from its JPEG frames with the weight-free detector by
:func:`~broadtrack_graph.actions.track.track_input`, in each requested mode. The run's
``summary.json`` carries the seconds spent per stage (``timings_s``: detect_s, flow_s,
solve_s, confidence_s, reinit_s, write_s in the tracking thread; markings_ahead_s, the
camera-free half of detection done ahead where the frames are decoded: a process of its own for a clip of 100
frames or more, :mod:`broadtrack_graph.track.ahead`); the suite adds the wall time and the CPU time of the whole
call, that process's included (which include reading and decoding the frames, and for batch mode the first pass
and the refinement), and per stage the milliseconds per frame, the share of the wall time and the stage's own
frames per second.

OpenCV runs with ``--threads`` threads (default 1); GTSAM has no TBB here and runs on one
thread. On a shared machine the wall time includes waiting for a core: compare it
with the CPU time.
"""

from __future__ import annotations

import logging
import time
from pathlib import Path

import cv2

from broadtrack_graph.benchmarks.options import add_reinit_model, tracker_options
from broadtrack_graph.io.process_prefetch import cpu_seconds
from broadtrack_graph.track.config import TrackingConfig

HELP = "fps of the whole tracking pipeline and of each stage (detect, flow, solve, confidence, reinit, write)"

log = logging.getLogger(__name__)

STAGES = ("detect_s", "flow_s", "solve_s", "confidence_s", "reinit_s", "write_s")
AHEAD_STAGES = ("markings_ahead_s",)
"""Stages run where the frames are decoded, overlapping STAGES (not part of their sum)."""


def add_arguments(parser) -> None:
    from broadtrack_graph.synth.presets import PRESETS
    from broadtrack_graph.types.modes import MODES

    parser.add_argument("--preset", default="main", choices=sorted(PRESETS), help="synthetic preset (default main)")
    parser.add_argument("--frames", type=int, default=200, help="frames of the clip (default 200)")
    parser.add_argument("--modes", nargs="+", default=["online"], choices=MODES, help="tracking modes (default online)")
    parser.add_argument("--width", type=int, default=1920)
    parser.add_argument("--height", type=int, default=1080)
    parser.add_argument("--seed", type=int, default=0, help="clip seed (default 0)")
    parser.add_argument("--lag", type=int, default=TrackingConfig.lag_frames,
                        help=f"fixed-lag smoother lag in frames (default {TrackingConfig.lag_frames})")
    parser.add_argument("--threads", type=int, default=1, help="OpenCV threads (default 1)")
    parser.add_argument("--out", type=Path, default=Path("bench-speed"),
                        help="folder for clips/ and runs/ (default ./bench-speed); a rendered clip found there is reused")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bars")
    add_reinit_model(parser)


def stage_figures(timings_s: dict, frames: int, wall_s: float) -> dict:
    """Per stage: total seconds, ms per frame, share of the wall time, and the stage's own fps.

    Args:
        timings_s: stage name -> seconds (the run summary's ``timings_s``).
        frames: frames processed.
        wall_s: wall time of the whole run, seconds.
    """
    out = {}
    for stage in STAGES:
        seconds = float(timings_s.get(stage, 0.0) or 0.0)
        out[stage.removesuffix("_s")] = {
            "total_s": round(seconds, 3),
            "ms_per_frame": round(1000.0 * seconds / max(frames, 1), 2),
            "share_of_wall": round(seconds / wall_s, 4) if wall_s > 0 else None,
            "fps": round(frames / seconds, 2) if seconds > 0 else None,
        }
    accounted = sum(float(timings_s.get(stage, 0.0) or 0.0) for stage in STAGES)
    other = max(wall_s - accounted, 0.0)
    out["other"] = {  # frame reading / decoding, bookkeeping, batch refinement
        "total_s": round(other, 3),
        "ms_per_frame": round(1000.0 * other / max(frames, 1), 2),
        "share_of_wall": round(other / wall_s, 4) if wall_s > 0 else None,
        "fps": None,
    }
    return out


def run(args) -> dict:
    from broadtrack_graph.actions.track import DetectorOptions, track_input
    from broadtrack_graph.benchmarks.accuracy import prepare_suite
    from broadtrack_graph.benchmarks.clips import ensure_clip, stage_timings

    progress, out = prepare_suite(args)
    started = time.perf_counter()
    clip, rendered = ensure_clip(out / "clips", args.preset, args.frames, args.width, args.height, args.seed, progress)
    report: dict = {
        "preset": args.preset, "frames": args.frames, "width_px": args.width, "height_px": args.height,
        "seed": args.seed, "opencv_threads": cv2.getNumThreads(), "detector": "weightfree",
        "clip": {"path": str(clip), "rendered_now": rendered,
                 "render_s": round(time.perf_counter() - started, 2) if rendered else None},
        "modes": {},
    }
    for mode in args.modes:
        config = TrackingConfig(mode=mode, lag_frames=args.lag, **tracker_options(args))
        run_dir = out / "runs" / f"{args.preset}-{mode}"
        cpu0, wall0 = _cpu_s(), time.perf_counter()
        result = track_input(clip, run_dir, config, DetectorOptions("weightfree"), progress=progress)
        wall_s, cpu_s = time.perf_counter() - wall0, _cpu_s() - cpu0
        summary = result.summary
        frames = int(summary.get("frames_written", 0))
        timings = stage_timings(summary)  # batch: the first pass's stages; the refinement is in "other"
        report["modes"][mode] = {
            "frames": frames,
            "wall_s": round(wall_s, 3),
            "cpu_s": round(cpu_s, 3),
            "fps_wall": round(frames / wall_s, 3) if wall_s > 0 else None,
            "fps_cpu": round(frames / cpu_s, 3) if cpu_s > 0 else None,
            "fps_summary": summary.get("fps"),
            "batch_refine_s": summary.get("batch_refine_s"),
            "reinitialisations": summary.get("reinitialisations"),
            "stages": stage_figures(timings, frames, wall_s),
            "ahead_ms_per_frame": {stage.removesuffix("_s"): round(1000.0 * float(timings.get(stage) or 0.0)
                                                                   / max(frames, 1), 2) for stage in AHEAD_STAGES},
            "run": str(run_dir),
        }
    return report


def _cpu_s() -> float:
    """CPU seconds of this process, all its threads, and of the process that prepared the frames once it ended."""
    return cpu_seconds()
