"""``broadtrack-graph bench graph``: accuracy, smoothness and speed of the graph solvers.

Accuracy mode (default): a synthetic clip (``synth.motion`` preset, ``--frames``) with
ground-truth projections of the pitch + noise + gross outliers and flow matches; runs
the online tracker, the fixed-lag smoother and the batch refiner (tripod estimated)
and reports reprojection errors against the truth, frame-to-frame jitter of pan, tilt
and f, the recovered tripod, and what an observation-free stretch does to the
uncertainty. ``--plot`` writes a PNG.

Speed mode (``--speed-frames N``): the online tracker alone over N frames, timing each
update (observation simulation excluded) and sampling the resident memory.
"""

from __future__ import annotations

import dataclasses
import logging
import math
import time
from pathlib import Path

import numpy as np
from tqdm import tqdm

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.graph.batch import BatchRefiner
from broadtrack_graph.graph.config import GraphConfig, MeasurementSigmas, SolverSettings
from broadtrack_graph.graph.estimates import EstimateSequence
from broadtrack_graph.graph.fixed_lag import FixedLagSmoother
from broadtrack_graph.graph.online import OnlineTracker
from broadtrack_graph.graph.simulate import SimulationSettings, reprojection_error_px, simulate_frames
from broadtrack_graph.synth.motion import generate_camera_track

HELP = "graph solvers: accuracy / smoothness of online, fixed-lag and batch, or online speed and memory"

logger = logging.getLogger(__name__)


def add_arguments(parser) -> None:
    parser.add_argument("--frames", type=int, default=750, help="clip length for the accuracy run (default 750)")
    parser.add_argument("--preset", default="main", help="camera motion preset of synth.motion (default main)")
    parser.add_argument("--width", type=int, default=960, help="image width in pixels (default 960)")
    parser.add_argument("--height", type=int, default=540, help="image height in pixels (default 540)")
    parser.add_argument("--line-points", type=int, default=300, help="line points per frame (default 300)")
    parser.add_argument("--flow-matches", type=int, default=700, help="flow matches per frame (default 700)")
    parser.add_argument("--keypoints", type=int, default=0, help="keypoints per frame (default 0)")
    parser.add_argument("--noise-px", type=float, default=1.0, help="pixel noise sigma (default 1)")
    parser.add_argument("--outliers", type=float, default=0.1, help="share of gross outliers (default 0.1)")
    parser.add_argument("--lag", type=int, default=25, help="fixed-lag smoother lag in frames (default 25)")
    parser.add_argument("--window", type=int, default=None, help="online smoother window in frames (default: config)")
    parser.add_argument("--empty", default="", help="frames without observations, e.g. 400-409 (default none)")
    parser.add_argument("--tripod-model", default="distance", choices=("distance", "axis_point"),
                        help="tripod factor: the paper's distance L_T or the full axis-point model (default distance)")
    parser.add_argument("--no-delta-prior", action="store_true",
                        help="batch: no prior on the tripod's delta (default: 0.2 m +- 0.1 m, see tripod_fit)")
    parser.add_argument("--no-batch", action="store_true", help="skip the batch refinement")
    parser.add_argument("--no-uncertainty", action="store_true", help="skip marginal covariances")
    parser.add_argument("--seed", type=int, default=0, help="random seed (default 0)")
    parser.add_argument("--speed-frames", type=int, default=0, help="speed mode: online tracker over this many frames")
    parser.add_argument("--plot", type=Path, default=None, help="write a PNG of the accuracy run here")


def _parse_range(text: str) -> list[int]:
    out: list[int] = []
    for part in filter(None, (p.strip() for p in text.split(","))):
        lo, _, hi = part.partition("-")
        out += list(range(int(lo), int(hi or lo) + 1))
    return out


def _config(args) -> GraphConfig:
    solver = SolverSettings(compute_uncertainty=not args.no_uncertainty)
    if args.window:
        solver = dataclasses.replace(solver, window_frames=args.window)
    if getattr(args, "no_delta_prior", False):
        solver = dataclasses.replace(solver, tripod_delta_prior_m=None)
    return GraphConfig(solver=solver, measurements=MeasurementSigmas(tripod_model=getattr(args, "tripod_model", "distance")))


def _settings(args) -> SimulationSettings:
    return SimulationSettings(
        line_points=args.line_points, flow_matches=args.flow_matches, keypoints=args.keypoints,
        noise_px=args.noise_px, outlier_ratio=args.outliers,
    )


def _rss_mb() -> float:
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def run(args) -> dict:
    if args.speed_frames:
        return _speed(args)
    return _accuracy(args)


# --------------------------------------------------------------------------- accuracy


def _errors(cameras, truth, pitch) -> np.ndarray:
    return np.array([reprojection_error_px(c, g, pitch) if c is not None else np.inf for c, g in zip(cameras, truth)])


def _jitter(cameras, truth) -> dict:
    """RMS of the frame-to-frame change of the estimation error (0 for a smooth bias), and the
    RMS second difference of the estimates themselves next to the truth's."""
    est = np.array([c.to_vector() for c in cameras])
    gt = np.array([c.to_vector() for c in truth])
    err = est - gt
    out = {}
    for name, col, scale in (("pan_deg", 2, 180 / math.pi), ("tilt_deg", 3, 180 / math.pi), ("f_px", 0, 1.0)):
        out[name] = {
            "error_step_rms": float(np.sqrt(np.mean(np.diff(err[:, col]) ** 2)) * scale),
            "second_difference_rms": float(np.sqrt(np.mean(np.diff(est[:, col], 2) ** 2)) * scale),
            "truth_second_difference_rms": float(np.sqrt(np.mean(np.diff(gt[:, col], 2) ** 2)) * scale),
        }
    return out


def _finite_or_none(value) -> float | None:
    value = float(value)
    return value if math.isfinite(value) else None


def _summary(errors: np.ndarray) -> dict:
    """Error statistics over frames whose true camera sees markings (NaN errors left out)."""
    seen = errors[~np.isnan(errors)]
    return {
        "median_reprojection_px": _finite_or_none(np.median(seen)),
        "mean_reprojection_px": _finite_or_none(np.mean(seen)),
        "p90_reprojection_px": _finite_or_none(np.percentile(seen, 90)),
        "max_reprojection_px": _finite_or_none(np.max(seen)),
        "frames_scored": int(len(seen)),
    }


def _accuracy(args) -> dict:
    pitch = PitchTemplate()
    W, H = args.width, args.height
    truth_track = generate_camera_track(args.preset, args.frames, W, H, seed=args.seed)
    truth = truth_track.cameras
    empty = [i for i in _parse_range(args.empty) if 0 < i < args.frames]
    observations = list(simulate_frames(truth, pitch, _settings(args), seed=args.seed + 1, empty_frames=empty))
    config = _config(args)
    report: dict = {"mode": "accuracy", "frames": args.frames, "preset": args.preset, "resolution": [W, H],
                    "tripod_model": config.measurements.tripod_model,
                    "tripod_delta_prior_m": config.solver.tripod_delta_prior_m,
                    "line_points": args.line_points, "flow_matches": args.flow_matches, "noise_px": args.noise_px,
                    "outlier_ratio": args.outliers, "lag": args.lag, "empty_frames": empty}
    # Online (the tripod is unknown at the start of a clip: no tripod factor).
    tracker = OnlineTracker(W, H, pitch, config)
    times = []
    online = EstimateSequence()
    for i, obs in enumerate(tqdm(observations, desc="online", unit="frame")):
        t0 = time.perf_counter()
        online.frames.append(tracker.add_frame(obs, initial_guess=truth[0] if i == 0 else None))
        times.append(time.perf_counter() - t0)
    report["online"] = {**_summary(_errors(online.cameras(), truth, pitch)), "jitter": _jitter(online.cameras(), truth),
                        "median_update_ms": 1000 * float(np.median(times)), "mean_update_ms": 1000 * float(np.mean(times))}
    # Fixed lag.
    smoother = FixedLagSmoother(W, H, pitch, config, lag=args.lag)
    lagged = EstimateSequence()
    times = []
    for i, obs in enumerate(tqdm(observations, desc=f"fixed lag {args.lag}", unit="frame")):
        t0 = time.perf_counter()
        lagged.frames += smoother.add_frame(obs, initial_guess=truth[0] if i == 0 else None)
        times.append(time.perf_counter() - t0)
    lagged.frames += smoother.finish()
    report["fixed_lag"] = {**_summary(_errors(lagged.cameras(), truth, pitch)), "jitter": _jitter(lagged.cameras(), truth),
                           "median_update_ms": 1000 * float(np.median(times)), "mean_update_ms": 1000 * float(np.mean(times))}
    batch = None
    if not args.no_batch:
        refiner = BatchRefiner(W, H, pitch, config)
        t0 = time.perf_counter()
        batch, tripod = refiner.refine(observations, online, estimate_tripod=True, progress=True)
        elapsed = time.perf_counter() - t0
        report["batch"] = {**_summary(_errors(batch.cameras(), truth, pitch)), "jitter": _jitter(batch.cameras(), truth),
                           "seconds": elapsed, "chunks": refiner.last_info["chunks"]}
        fit = refiner.last_info.get("tripod_fit", {})
        if tripod is not None:
            report["tripod"] = {
                "true_T_w": list(truth_track.tripod.T_w), "true_delta_m": truth_track.tripod.delta_m,
                "estimated_T_w": list(tripod.T_w), "estimated_delta_m": tripod.delta_m,
                "T_error_m": float(np.linalg.norm(np.subtract(tripod.T_w, truth_track.tripod.T_w))),
                "T_error_xyz_m": list(np.subtract(tripod.T_w, truth_track.tripod.T_w)),
                "delta_error_m": float(tripod.delta_m - truth_track.tripod.delta_m),
                "fit_from_online": {k: fit.get(k) for k in ("inlier_ratio", "rms_inlier_m", "condition", "std_T_m", "std_delta_m", "reason")},
                "batch_tripod_std": refiner.last_info["chunks"][0].get("tripod_std"),
                "tilt_range_deg": float(np.degrees(np.ptp([c.tilt_rad for c in truth]))),
            }
    if empty and not args.no_uncertainty:
        before = online[empty[0] - 1].std
        inside = [online[i].std for i in empty]
        report["empty_stretch"] = {
            "frames": [empty[0], empty[-1]],
            "pan_std_deg_before": float(np.degrees(before[2])),
            "pan_std_deg_last_empty": float(np.degrees(inside[-1][2])),
            "f_std_px_before": float(before[0]), "f_std_px_last_empty": float(inside[-1][0]),
            "reprojection_px_last_empty": float(reprojection_error_px(online[empty[-1]].camera, truth[empty[-1]], pitch)),
            "reprojection_px_5_frames_after": float(reprojection_error_px(online[min(empty[-1] + 5, len(truth) - 1)].camera, truth[min(empty[-1] + 5, len(truth) - 1)], pitch)),
            "active_factors_in_empty_frame": online[empty[0]].active_factors,
        }
    if args.plot is not None:
        _plot(args.plot, truth, {"online": online, f"fixed lag {args.lag}": lagged, **({"batch": batch} if batch else {})}, pitch, empty)
        report["plot"] = str(args.plot)
    return report


def _plot(path: Path, truth, tracks: dict, pitch, empty) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    frames = np.arange(len(truth))
    gt = np.array([c.to_vector() for c in truth])
    fig, axes = plt.subplots(5, 1, figsize=(12, 14), sharex=True)
    for name, track in tracks.items():
        est = track.states()
        axes[0].plot(frames, _errors(track.cameras(), truth, pitch), label=name, lw=0.8)
        axes[1].plot(frames, np.degrees(est[:, 2] - gt[:, 2]), label=name, lw=0.8)
        axes[2].plot(frames, np.degrees(est[:, 3] - gt[:, 3]), label=name, lw=0.8)
        axes[3].plot(frames, est[:, 0] - gt[:, 0], label=name, lw=0.8)
        std = np.array([f.std if f.std is not None else np.full(8, np.nan) for f in track])
        axes[4].semilogy(frames, np.degrees(std[:, 2]), label=f"{name} pan std", lw=0.8)
    axes[0].set_ylabel("reprojection error (px)")
    axes[0].set_yscale("log")
    axes[1].set_ylabel("pan error (deg)")
    axes[2].set_ylabel("tilt error (deg)")
    axes[3].set_ylabel("f error (px)")
    axes[4].set_ylabel("marginal std pan (deg)")
    axes[4].set_xlabel("frame")
    for ax in axes:
        for i in empty:
            ax.axvspan(i - 0.5, i + 0.5, color="0.85", lw=0)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=8, loc="upper right")
    fig.suptitle("graph solvers on a synthetic clip (grey: frames without observations)")
    fig.tight_layout()
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=100)
    plt.close(fig)


# --------------------------------------------------------------------------- speed


def _speed(args) -> dict:
    pitch = PitchTemplate()
    W, H = args.width, args.height
    count = args.speed_frames
    truth = generate_camera_track(args.preset, count, W, H, seed=args.seed).cameras
    config = _config(args)
    tracker = OnlineTracker(W, H, pitch, config)
    times = np.zeros(count)
    memory = []
    errors = []
    rss_start = _rss_mb()
    stream = simulate_frames(truth, pitch, _settings(args), seed=args.seed + 1)
    for i, obs in enumerate(tqdm(stream, total=count, desc="online speed", unit="frame")):
        t0 = time.perf_counter()
        estimate = tracker.add_frame(obs, initial_guess=truth[0] if i == 0 else None)
        times[i] = time.perf_counter() - t0
        if i % 500 == 0 or i == count - 1:
            memory.append((i, _rss_mb()))
            errors.append(reprojection_error_px(estimate.camera, truth[i], pitch) if estimate.camera is not None else np.inf)
    block = min(1000, max(1, count // 4))
    first, last = np.median(times[:block]), np.median(times[-block:])
    return {
        "mode": "speed", "frames": count, "preset": args.preset, "resolution": [W, H],
        "line_points": args.line_points, "flow_matches": args.flow_matches,
        "window_frames": tracker.window_frames, "uncertainty": not args.no_uncertainty,
        "median_update_ms": 1000 * float(np.median(times)),
        "p90_update_ms": 1000 * float(np.percentile(times, 90)),
        "max_update_ms": 1000 * float(np.max(times)),
        "block_frames": block,
        "median_update_ms_per_block": [
            [int(lo), round(1000 * float(np.median(times[lo : lo + block])), 3)]
            for lo in range(0, count, max(block, count // 20))
        ],
        "median_update_ms_first_block": 1000 * float(first),
        "median_update_ms_last_block": 1000 * float(last),
        "last_over_first": float(last / first),
        "rss_mb_at_start": rss_start,
        "rss_mb_samples": memory[:: max(1, len(memory) // 20)] + [memory[-1]],
        "rss_growth_mb_after_first_block": float(memory[-1][1] - next(m for f, m in memory if f >= block)) if count > block else None,
        "sampled_reprojection_px_median": _finite_or_none(np.nanmedian(errors)),
        "sampled_reprojection_px_max": _finite_or_none(np.nanmax(errors)),
        "sampled_frames_without_visible_markings": int(np.isnan(errors).sum()),
    }
