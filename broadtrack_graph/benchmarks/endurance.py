"""``broadtrack-graph bench endurance``: a long clip tracked online, per-block time and memory, and a killed run.

The product's claim (README.md, "Modes"): online tracking keeps a flat per-frame cost over a
match, and an interrupted run keeps every frame it wrote. This suite measures both.

The clip. A segment of ``--unique-frames`` frames of a synthetic preset (default ``long``,
1920x1080) is rendered once (:func:`~broadtrack_graph.benchmarks.clips.ensure_clip`,
reused from ``--out`` when present) and the ``--frames``-frame clip (default 20,000) is a
folder of numbered images that plays the segment forwards, backwards, forwards...
(``frames/000001.jpg`` ... as symbolic links to the segment's JPEGs; see
:func:`pingpong_index`). The camera path stays continuous (the motion reverses at each end
of the segment) and every frame keeps its exact ground truth: the segment frame it shows.
Rendering an HD frame costs more than tracking it (``bench render``'s figure: docs/BENCHMARKS.md), so
20,000 unique frames would take hours; with ``--unique-frames`` >= ``--frames`` the clip is rendered in
full and played once.
Tracking reads JPEG frames, so its time never includes rendering.

The tracked run. The clip is tracked online with the weight-free detector through the
product's own loop (:class:`~broadtrack_graph.track.frame_loop.TrackingRun` and
:func:`~broadtrack_graph.track.feed.run_loop`, as :func:`~broadtrack_graph.actions.track.track_input`
builds them: frames prefetched and decoded in a background thread). Each call of
``TrackingRun.process`` is timed (wall clock and the main thread's CPU time: on a shared
machine the CPU time is the steadier figure); the process RSS (``VmRSS`` of
``/proc/self/status``) is sampled every 100 frames. Per block of ``--block`` frames
(default 1000): median / p90 / max ms per frame, median CPU ms, median interval between
finished frames (includes waiting for a decoded frame), RSS at the block's end, counts of
re-initialisations and of frames per non-tracked status, and against the ground truth on
every ``--eval-every``-th frame: the SoccerNet JaC@5, MRE (px) and the pan / focal error
of the estimate. Flatness: last-block / first-block median ratios and the linear trend of
the block medians and of the RSS after the first block.

The killed run. ``broadtrack-graph track`` runs on the same clip as a subprocess and is
sent SIGKILL once its ``track.jsonl`` holds ``--kill-fraction`` of the frames (default
0.5; ``--no-kill`` skips this step). Then every ``camera_*.json`` must read
(:func:`~broadtrack_graph.io.cameras.read_camera_file`), ``track.jsonl`` must read with
:func:`~broadtrack_graph.io.run_folder.read_track`, and the two must agree (every record
with a camera has its file, with the same camera; at most one file of the frame in flight
has no line yet); its cameras are compared with the full run's on the same frames (the
same code tracks the same frames identically; ``same_code_as_tracked_run`` says whether the
package sources changed on disk between the two runs, which a shared working tree allows).

Outputs: the JSON report (stdout, ``--json``), a plot (``--plot``, default
``OUT/endurance.png``: ms/frame, RSS and JaC@5 per block against the frame index) and
``OUT/per_frame.csv`` (frame, process_ms, cpu_ms, interval_ms).

The modules: the clip (:mod:`~broadtrack_graph.benchmarks.endurance_clip`), time and memory
(:mod:`~broadtrack_graph.benchmarks.process_stats`), the block figures and plot
(:mod:`~broadtrack_graph.benchmarks.endurance_figures`) and the killed run
(:mod:`~broadtrack_graph.benchmarks.endurance_kill`); this one holds the arguments and the run.
"""

from __future__ import annotations

import logging
import time
from pathlib import Path

import cv2
import numpy as np

from broadtrack_graph.benchmarks.endurance_clip import ensure_endurance_clip
from broadtrack_graph.benchmarks.endurance_figures import (
    block_figures,
    flatness,
    ground_truth_scores,
    plot_blocks,
    stats_ms,
    write_per_frame_csv,
)
from broadtrack_graph.benchmarks.endurance_kill import check_interrupted_run, kill_track_run, source_digest
from broadtrack_graph.benchmarks.process_stats import FrameClock

HELP = ("endurance: track a 20,000-frame clip online (ms/frame and RSS per 1000 frames, JaC@5), "
        "then kill a track run halfway and check that every frame it wrote reads back")

log = logging.getLogger(__name__)


def add_arguments(parser) -> None:
    from broadtrack_graph.synth.presets import PRESETS

    parser.add_argument("--preset", default="long", choices=sorted(PRESETS), help="synthetic preset (default long)")
    parser.add_argument("--frames", type=int, default=20000, help="frames of the tracked clip (default 20000)")
    parser.add_argument("--unique-frames", type=int, default=1000,
                        help="frames actually rendered; the clip plays them forwards and backwards until --frames "
                             "(default 1000; >= --frames renders the whole clip)")
    parser.add_argument("--width", type=int, default=1920)
    parser.add_argument("--height", type=int, default=1080)
    parser.add_argument("--seed", type=int, default=0, help="clip seed (default 0)")
    parser.add_argument("--block", type=int, default=1000, help="frames per reported block (default 1000)")
    parser.add_argument("--eval-every", type=int, default=10,
                        help="score every N-th frame against the ground truth (default 10; 0: no scoring)")
    parser.add_argument("--threads", type=int, default=1, help="OpenCV threads (default 1)")
    parser.add_argument("--no-kill", action="store_true", help="skip the killed-run check")
    parser.add_argument("--kill-fraction", type=float, default=0.5,
                        help="SIGKILL the track subprocess once this share of the frames is written (default 0.5)")
    parser.add_argument("--out", type=Path, default=Path("bench-endurance"),
                        help="folder for clips/, runs/ and per_frame.csv (default ./bench-endurance); a rendered "
                             "segment found there is reused")
    parser.add_argument("--plot", type=Path, default=None, help="plot file (default OUT/endurance.png)")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bars")


def track_timed(clip: Path, run_dir: Path, config, progress: bool, block: int | None = None):
    """Track an image folder online as ``track_input`` does, with every frame timed.

    Returns:
        (RunResult, FrameClock).
    """
    from broadtrack_graph.actions.track import DetectorOptions, make_detector
    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.io.frames import open_frames
    from broadtrack_graph.track.feed import run_loop
    from broadtrack_graph.track.frame_loop import TrackingRun
    from broadtrack_graph.track.inputs import frames_from_source
    from broadtrack_graph.track.run_context import RunContext

    pitch = PitchTemplate()
    with open_frames(clip) as source:
        run_info = {"input": str(clip), "detections": None, "detector": "weightfree", "source": source.describe()}
        context = RunContext(config, make_detector(DetectorOptions("weightfree"), pitch), pitch, run_info=run_info,
                             progress=progress)
        run = TrackingRun(source.width_px, source.height_px, run_dir, context)
        clock = FrameClock(run, block=block)
        run_loop(run, frames_from_source(source), len(source), config.mode)
        clock.sample_rss()  # after the last frame
        return run.finish(), clock


def run(args) -> dict:
    from broadtrack_graph.benchmarks.accuracy import prepare_suite
    from broadtrack_graph.benchmarks.clips import ensure_clip
    from broadtrack_graph.benchmarks.speed import stage_figures
    from broadtrack_graph.errors import InputError
    from broadtrack_graph.track.config import TrackingConfig

    progress, out = prepare_suite(args)
    if args.unique_frames < 2 or args.block < 1 or not 0.0 < args.kill_fraction < 1.0:
        raise InputError(None, f"--unique-frames must be >= 2, --block >= 1 and --kill-fraction in (0, 1); got "
                               f"{args.unique_frames}, {args.block}, {args.kill_fraction}")
    unique = min(args.unique_frames, args.frames)
    started = time.perf_counter()
    segment, rendered = ensure_clip(out / "clips", args.preset, unique, args.width, args.height, args.seed, progress)
    render_s = round(time.perf_counter() - started, 2) if rendered else None
    clip, _ = ensure_endurance_clip(segment, out / "clips" / f"endurance-{args.frames}f-from-{segment.name}",
                                        args.frames, unique)
    report: dict = {
        "preset": args.preset, "frames": args.frames, "unique_frames": unique, "width_px": args.width,
        "height_px": args.height, "seed": args.seed, "block_frames": args.block, "eval_every": args.eval_every,
        "opencv_threads": cv2.getNumThreads(), "detector": "weightfree", "mode": "online",
        "clip": {"path": str(clip), "segment": str(segment), "segment_rendered_now": rendered, "render_s": render_s,
                 "render_s_per_frame": round(render_s / unique, 3) if render_s else None,
                 "playback": "forwards-backwards" if unique < args.frames else "once"},
    }

    config = TrackingConfig(mode="online")
    run_dir = out / "runs" / "online"
    report["source_digest"] = source_digest()
    cpu0, wall0 = time.process_time(), time.perf_counter()
    result, clock = track_timed(clip, run_dir, config, progress, args.block)
    wall_s, cpu_s = time.perf_counter() - wall0, time.process_time() - cpu0
    summary = result.summary
    frames = int(summary.get("frames_written", 0))
    scores = ground_truth_scores(result.records, segment, unique, args.width, args.height, args.eval_every)
    blocks = block_figures(clock, result.records, scores, args.block)
    scored = list(scores.values())
    with_error = [s for s in scored if s["mre_px"] is not None]
    report["tracking"] = {
        "frames": frames, "wall_s": round(wall_s, 2), "cpu_s_process": round(cpu_s, 2),
        "fps_wall": round(frames / wall_s, 3) if wall_s > 0 else None,
        "ms_per_frame": stats_ms(clock.process_ms),
        "cpu_ms_median": round(float(np.median(clock.cpu_ms)), 3) if clock.cpu_ms else None,
        "status_counts": summary.get("status_counts"),
        "reinitialisations": summary.get("reinitialisations"),
        "solver_restarts": summary.get("solver_restarts"),
        "tripod": summary.get("tripod"),
        "stages": stage_figures(summary.get("timings_s") or {}, frames, wall_s),
        "scored_frames": len(scored),
        "jac_5": round(float(np.mean([s["jac_5"] for s in scored])), 4) if scored else None,
        "mre_px": round(float(np.mean([s["mre_px"] for s in with_error])), 3) if with_error else None,
        "run": str(run_dir),
    }
    report["flatness"] = flatness(blocks, clock)
    report["blocks"] = blocks
    report["rss_samples_mb"] = [[count, round(mb, 1)] for count, mb in clock.rss]  # [frames done, MB]
    csv_path = out / "per_frame.csv"
    write_per_frame_csv(csv_path, clock)
    plot_path = args.plot or out / "endurance.png"
    plot_blocks(plot_path, blocks, clock, f"bench endurance: {args.preset}, {frames} frames ({unique} rendered), "
                                          f"{args.width}x{args.height}, online, weight-free detector")
    report["files"] = {"plot": str(plot_path), "per_frame_csv": str(csv_path)}

    if args.no_kill:
        report["interrupted"] = None
        return report
    kill_after = max(1, int(round(args.kill_fraction * args.frames)))
    # Generous: 10x the measured time per frame of the full run, plus the start-up.
    timeout_s = 120.0 + 10.0 * kill_after * (wall_s / max(frames, 1))
    killed_dir = out / "runs" / "killed"
    digest = source_digest()
    launched = kill_track_run(clip, killed_dir, kill_after, timeout_s)
    same_code = digest == report["source_digest"] == source_digest()
    if not same_code:
        log.warning("the package sources changed during the benchmark: the killed run is not comparable frame by "
                    "frame with the tracked run")
    report["interrupted"] = {"kill_after_lines": kill_after, **launched, "source_digest": digest,
                             "same_code_as_tracked_run": same_code,
                             **check_interrupted_run(killed_dir, result.records)}
    return report
