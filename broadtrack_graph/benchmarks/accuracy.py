"""``broadtrack-graph bench accuracy``: the whole tracker on rendered clips, against exact ground truth.

For every synthetic preset (default main and 16m, 1920x1080) a clip is rendered once
(:func:`~broadtrack_graph.synth.writer.write_synthetic_clip`, reused from ``--out`` when
it is already there) and tracked with the weight-free detector in every mode
(online iSAM2, fixed-lag smoother, batch two-pass refinement) by
:func:`~broadtrack_graph.actions.track.track_input`. Each run is scored with the compare
helpers (:mod:`broadtrack_graph.metrics.compare`, which call
:func:`broadtrack_graph.metrics.soccernet.evaluate_cameras`):

* SoccerNet metric on the clip's line annotations: JaC@5, JaC@10 (accuracy), completeness,
  final score at 5 px, MRE / MedRE (px, at 1920x1080 when the clip is);
* errors of the camera parameters against the ground-truth cameras (pan / tilt / roll RMS,
  focal length mean |relative| error, focal point RMS), jitter (RMS second difference);
* the reliability of the written cameras: their confidence against whether they are right
  (every marking the true camera shows laid within 5 px of its true image at 960 x 540), grouped by
  confidence, per run and pooled over the presets per mode
  (:mod:`~broadtrack_graph.benchmarks.reliability`);
* the fitted tripod against the clip's ``tripod.json``: |T - T_true|, its horizontal part
  (the height of T is weakly observable with a main camera) and delta error. A run folder
  has ``tripod.json`` once a tripod is fitted (batch always; online after
  ``tripod_fit_frames`` frames).

The ablation (as in the paper's table) switches the optical-flow factor, the tripod
factor and k1 off one at a time (``TrackingConfig(use_flow=..., use_tripod=...,
estimate_k1=...)``), each on the preset made to need it (``--ablation FACTOR:PRESET``):
flow on ``hard`` (fast sweeps and tight zooms on bare grass: markings blur away or leave
the frame), the tripod on ``16m`` (tight zoom on few markings: the focal point slides
along the optical axis against the focal length) and k1 on ``wide`` (a wide lens with
strong distortion). An optional third field picks the clip's seed (``flow:hard:3``;
default ``--seed``): the default takes hard seed 3, whose first 200 frames hold 118
frames moving more than 40 px per frame and 110 at f > 5000 px, where hard seed 0's
first 200 frames never move faster than 31 px per frame and never zoom that tight
(``synth.motion.generate_camera_track`` shows it without rendering); and 16m seed 2,
whose far touchline runs within a few pixels of the board bases, so that without the
tripod the biased far points walk the focal point 1-2 m (seed 0 has no such bias and
tracks equally well with and without the tripod). Each pair is the
full tracker and the tracker without that factor on the same clip. Its default mode is batch: without a known tripod the online modes only
use the tripod term after fitting it on their first confident frames, so on a short
clip "no tripod" would differ from "full" on few frames.

Per preset (and for the ablation) the comparison table and plots are written to
``OUT/compare/<group>/`` (compare.md, series.png, focal_points.png).
"""

from __future__ import annotations

import json
import logging
import time
from dataclasses import replace
from pathlib import Path

import cv2
import numpy as np

from broadtrack_graph.benchmarks.clips import ensure_clip, stage_timings, track_clip
from broadtrack_graph.benchmarks.options import add_reinit_model, tracker_options
from broadtrack_graph.benchmarks.reliability import add_reliability, pooled
from broadtrack_graph.io.run_folder import RunFolder
from broadtrack_graph.track.config import TrackingConfig

HELP = "tracking accuracy on rendered clips: JaC@5/10, MRE, completeness per preset and mode; flow/tripod/k1 ablation"

log = logging.getLogger(__name__)

# Ablated factor -> the TrackingConfig change that switches it off.
ABLATION_FACTORS = {
    "flow": {"use_flow": False},
    "tripod": {"use_tripod": False},
    "k1": {"estimate_k1": False},
}
DEFAULT_ABLATION = ("flow:hard:3", "tripod:16m:2", "k1:wide")
"""Each factor on the preset made to need it."""


def parse_ablation(items, default_seed: int = 0) -> list[tuple[str, str, int]]:
    """``["flow:hard:3", "k1:wide"]`` -> ``[("flow", "hard", 3), ("k1", "wide", default_seed)]``.

    InputError on an unknown factor or preset or a seed that is not an integer.
    """
    from broadtrack_graph.errors import InputError
    from broadtrack_graph.synth.presets import PRESETS

    triples = []
    for item in items:
        factor, _, rest = str(item).partition(":")
        preset, _, seed = rest.partition(":")
        if factor not in ABLATION_FACTORS or preset not in PRESETS or (seed and not seed.isdigit()):
            raise InputError(None, f"--ablation {item!r}: expected FACTOR:PRESET[:SEED] with FACTOR in "
                                   f"{sorted(ABLATION_FACTORS)} and PRESET in {sorted(PRESETS)}")
        triples.append((factor, preset, int(seed) if seed else int(default_seed)))
    return triples


def add_arguments(parser) -> None:
    from broadtrack_graph.synth.presets import PRESETS
    from broadtrack_graph.types.modes import MODES

    add_reinit_model(parser)
    parser.add_argument("--presets", nargs="+", default=["main", "16m"], choices=sorted(PRESETS),
                        help="synthetic presets (default main 16m)")
    parser.add_argument("--frames", type=int, default=200, help="frames per clip (default 200)")
    parser.add_argument("--modes", nargs="+", default=list(MODES), choices=MODES,
                        help="tracking modes (default online fixed-lag batch)")
    parser.add_argument("--ablation", nargs="*", default=list(DEFAULT_ABLATION), metavar="FACTOR:PRESET[:SEED]",
                        help="factors to switch off, each on its preset and seed (default: flow:hard:3 tripod:16m:2 "
                             "k1:wide, seed --seed when not given); give none to skip the ablation")
    parser.add_argument("--ablation-mode", default="batch", choices=MODES, help="mode of the ablation runs (default batch)")
    parser.add_argument("--seed", type=int, default=0, help="clip seed (default 0)")
    parser.add_argument("--width", type=int, default=1920)
    parser.add_argument("--height", type=int, default=1080)
    parser.add_argument("--lag", type=int, default=TrackingConfig.lag_frames,
                        help=f"fixed-lag smoother lag in frames (default {TrackingConfig.lag_frames})")
    parser.add_argument("--out", type=Path, default=Path("bench-accuracy"),
                        help="folder for clips/, runs/ and compare/ (default ./bench-accuracy); rendered clips found "
                             "there are reused")
    parser.add_argument("--reuse-runs", action="store_true",
                        help="also reuse finished runs whose configuration matches (default: track again)")
    parser.add_argument("--threads", type=int, default=1, help="OpenCV threads (default 1)")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bars")


# --------------------------------------------------------------------------- clips and runs


# --------------------------------------------------------------------------- figures


def tripod_error(run_dir: Path, truth_path: Path) -> dict | None:
    """The run's fitted tripod (``run_dir/tripod.json``) against the clip's, or None without one.

    Returns:
        {"T_w", "delta_m", "T_error_m" |T - T_true|, "T_error_xy_m" horizontal part,
         "T_error_z_m" signed height error, "delta_error_m" signed}.
    """
    from broadtrack_graph.io.tripod_file import read_tripod

    fitted_path = RunFolder(run_dir).tripod_path
    if not fitted_path.is_file() or not truth_path.is_file():
        return None
    fitted, truth = read_tripod(fitted_path), read_tripod(truth_path)
    error = np.asarray(fitted.T_w, float) - np.asarray(truth.T_w, float)
    return {
        "T_w": [round(float(v), 4) for v in fitted.T_w],
        "delta_m": round(float(fitted.delta_m), 4),
        "T_error_m": round(float(np.linalg.norm(error)), 4),
        "T_error_xy_m": round(float(np.linalg.norm(error[:2])), 4),
        "T_error_z_m": round(float(error[2]), 4),
        "delta_error_m": round(float(fitted.delta_m - truth.delta_m), 4),
    }


def _r(value, digits: int = 4):
    return None if value is None else round(float(value), digits)


def run_figures(stats: dict | None, tracked: dict, tripod: dict | None) -> dict:
    """The figures of one run from its compare statistics, tracking call and tripod error.

    ``stats`` is None for a run that wrote no frame (all figures None, the error kept).
    """
    if stats is None:
        return {"error": tracked["error"], "frames_written": tracked["frames_written"], "track_wall_s": tracked["wall_s"]}
    metrics = stats.get("metrics") or {}
    gt = stats.get("ground_truth_error") or {}
    summary = tracked["summary"]
    jitter = stats["jitter"]
    return {
        "error": tracked["error"],
        "jac_5": _r(metrics.get("jac", {}).get("5")),
        "jac_10": _r(metrics.get("jac", {}).get("10")),
        "completeness": _r(metrics.get("completeness")),
        "final_score_5": _r(metrics.get("final_score", {}).get("5")),
        "mre_px": _r(metrics.get("mre_px"), 3),
        "medre_px": _r(metrics.get("medre_px"), 3),
        "frames": stats["frames"],
        "frames_with_camera": stats["frames_with_camera"],
        "reinitialisations": stats["reinitialisations"],
        "status_counts": summary.get("status_counts"),
        "gt_pan_rms_deg": _r(gt.get("pan_rms_deg")),
        "gt_tilt_rms_deg": _r(gt.get("tilt_rms_deg")),
        "gt_roll_rms_deg": _r(gt.get("roll_rms_deg")),
        "gt_focal_mean_abs_rel_pct": _r(gt.get("focal_mean_abs_rel_pct"), 3),
        "gt_position_rms_m": _r(gt.get("position_rms_m"), 3),
        "jitter_d2_pan_deg": _r(jitter["pan_deg"]["rms_d2"], 5),
        "jitter_d2_tilt_deg": _r(jitter["tilt_deg"]["rms_d2"], 5),
        "jitter_d2_focal_px": _r(jitter["focal_px"]["rms_d2"], 3),
        "focal_point_rms_to_mean_m": _r(stats["focal_point"]["rms_to_mean_m"], 3),
        "tripod": tripod,
        "track_wall_s": tracked["wall_s"],
        "reused_run": tracked["reused"],
        "timings_s": stage_timings(summary),
    }


def compare_group(clip: Path, runs: dict[str, Path], out_dir: Path) -> dict:
    """compare_runs over the runs of one clip (metric, ground-truth errors, plots in out_dir).

    Runs without any written frame (crashed at once) are left out; their name maps to None
    in ``report["runs"]``.
    """
    from broadtrack_graph.actions.compare import compare_runs

    truth = json.loads((clip / "tripod.json").read_text(encoding="utf-8")) if (clip / "tripod.json").is_file() else None
    empty = [name for name, path in runs.items()
             if not RunFolder(path).has_track() or not RunFolder(path).track_path.read_text(encoding="utf-8").strip()]
    runs = {name: path for name, path in runs.items() if name not in empty}
    if not runs:
        return {"runs": dict.fromkeys(empty)}
    report = compare_runs(list(runs.values()), names=list(runs), annotations_path=clip / "Labels-GameState.json",
                        ground_truth_dir=clip / "cameras", out_dir=out_dir,
                        tripod_T_w=None if truth is None else truth["T_w"])
    report["runs"].update(dict.fromkeys(empty))
    return report


# --------------------------------------------------------------------------- the suite


def prepare_suite(args) -> tuple[bool, Path]:
    """Common start of the accuracy and speed suites: check --frames, set OpenCV threads.

    Returns:
        (progress bar on, output folder).
    """
    from broadtrack_graph.errors import InputError

    if args.frames < 2:
        raise InputError(None, f"--frames must be >= 2, got {args.frames}")
    cv2.setNumThreads(int(args.threads))
    return not args.no_progress, Path(args.out)


def run(args) -> dict:

    progress, out = prepare_suite(args)
    ablation = parse_ablation(args.ablation or [], args.seed)  # a bad --ablation fails before any tracking
    clips_dir, runs_dir, compare_dir = out / "clips", out / "runs", out / "compare"
    report: dict = {
        "width_px": args.width, "height_px": args.height, "frames": args.frames, "seed": args.seed,
        "modes": list(args.modes), "lag_frames": args.lag, "opencv_threads": cv2.getNumThreads(),
        "out": str(out), "clips": {}, "presets": {}, "ablation": None,
    }
    # (preset, run name) -> (clip, run dir, config); the tracking is done once per entry.
    done: dict[tuple[str, str], dict] = {}

    def tracked(preset: str, name: str, clip: Path, config) -> dict:
        key = (preset, name)
        if key not in done:
            log.info("tracking %s / %s", preset, name)
            done[key] = track_clip(clip, runs_dir / preset / name, config, args.reuse_runs, progress)
        return done[key]

    def group_name(preset: str, seed: int) -> str:
        """Key of a clip in the report and folder of its runs: the preset, plus the seed when not --seed."""
        return preset if seed == args.seed else f"{preset}-s{seed}"

    def clip_for(preset: str, seed: int | None = None) -> Path:
        seed = args.seed if seed is None else seed
        group = group_name(preset, seed)
        if group not in report["clips"]:
            started = time.perf_counter()
            clip, rendered = ensure_clip(clips_dir, preset, args.frames, args.width, args.height, seed, progress)
            report["clips"][group] = {"path": str(clip), "rendered_now": rendered,
                                      "render_s": round(time.perf_counter() - started, 2) if rendered else None}
        return Path(report["clips"][group]["path"])

    mode_configs = {mode: TrackingConfig(mode=mode, lag_frames=args.lag, **tracker_options(args))
                    for mode in args.modes}
    for preset in args.presets:
        clip = clip_for(preset)
        runs = {}
        for mode, config in mode_configs.items():
            tracked(preset, mode, clip, config)
            runs[mode] = runs_dir / preset / mode
        comparison = compare_group(clip, runs, compare_dir / preset)
        report["presets"][preset] = {
            name: run_figures(comparison["runs"][name], done[(preset, name)],
                              tripod_error(path, clip / "tripod.json"))
            for name, path in runs.items()
        }
        add_reliability(report["presets"][preset], runs, clip / "cameras")
        report["presets"][preset]["compare_md"] = comparison.get("files", {}).get("markdown")

    report["reliability"] = {mode: pooled([report["presets"][p][mode].get("reliability") for p in args.presets])
                             for mode in args.modes}
    if ablation:
        base = mode_configs.get(args.ablation_mode) or TrackingConfig(mode=args.ablation_mode, lag_frames=args.lag,
                                                                          **tracker_options(args))
        report["ablation"] = {"mode": args.ablation_mode, "factors": {}}
        for factor, preset, seed in ablation:
            clip = clip_for(preset, seed)
            group = group_name(preset, seed)
            # "with" is the preset's run of that mode when the suite tracked it already.
            names = {"with": args.ablation_mode, "without": f"{args.ablation_mode}-no-{factor}"}
            configs = {"with": base, "without": replace(base, **ABLATION_FACTORS[factor])}
            runs = {}
            for side in ("with", "without"):
                tracked(group, names[side], clip, configs[side])
                runs[side] = runs_dir / group / names[side]
            comparison = compare_group(clip, runs, compare_dir / f"ablation-{factor}-{group}")
            entry = {"preset": preset, "seed": seed, "compare_md": comparison.get("files", {}).get("markdown")}
            for side, path in runs.items():
                entry[side] = run_figures(comparison["runs"][side], done[(group, names[side])],
                                          tripod_error(path, clip / "tripod.json"))
            with_jac, without_jac = entry["with"].get("jac_5"), entry["without"].get("jac_5")
            entry["jac_5_gain"] = None if with_jac is None or without_jac is None else round(with_jac - without_jac, 4)
            with_mre, without_mre = entry["with"].get("mre_px"), entry["without"].get("mre_px")
            entry["mre_px_gain"] = None if with_mre is None or without_mre is None else round(without_mre - with_mre, 3)
            report["ablation"]["factors"][factor] = entry
    return report
