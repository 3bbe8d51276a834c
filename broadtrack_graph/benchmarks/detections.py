"""``broadtrack-graph bench detections``: tracking from precomputed detections (issue 7's two experiments).

One synthetic clip (rendered once into ``--clip``, reused when it is already there):

* ``files``: the project's weight-free detector writes a detections file
  (:func:`~broadtrack_graph.actions.detect.export_detections`, i.e. ``broadtrack-graph
  detect``; its naming tracker is the direct online run on the frames), then the clip is
  tracked from the file alone (no frames, no flow: online, fixed-lag, batch), from the
  file plus the frames (flow on: online, fixed-lag), and from the frames directly
  (fixed-lag; online = the naming run). Also the clip's own line annotations imported
  with :func:`~broadtrack_graph.actions.detect.import_annotations` (ground-truth
  lines driving the tracker). Each run is scored with the SoccerNet metric (JaC@5,
  JaC@10, completeness, MRE) against the clip's annotations.
* ``keypoints``: keypoints only (no lines): the clip's visible template keypoints with
  Gaussian pixel noise (``--kp-noise-px`` per axis) and a share ``--kp-mislabel`` given
  the name of another template keypoint (one the frame does not already hold), written
  as a detections file and tracked from it (online, fixed-lag, batch); compared with
  fitting each frame alone (:func:`~broadtrack_graph.reinit.lines.reinit_from_keypoints`,
  the pipeline's per-frame re-initialisation). Figures, over the frames where the
  per-frame fit and the track both have a camera: reprojection error of the pitch
  markings (every 1 m, the points the true camera sees; estimate vs truth, pixels;
  median over all points, and median over frames of the per-frame mean) and jitter
  (RMS of the first difference, per frame) of pan and focal length, also without the
  frames where the per-frame fit fails grossly (mean error above ``--kp-gross-px``),
  since a few such frames dominate an RMS.

``--plot [DIR]`` writes ``detections_files.png`` and ``detections_keypoints.png`` (into
``runs/bench-detections`` without a DIR).
"""

from __future__ import annotations

import logging
import time
from pathlib import Path

import numpy as np

from broadtrack_graph.io.detections_writer import named_keypoints_record
from broadtrack_graph.track.config import TrackingConfig

HELP = "tracking from detections files: detect -> file -> track, and keypoints-only smoothing vs per-frame fits"

log = logging.getLogger(__name__)


DEFAULT_PLOT_DIR = Path("runs/bench-detections")  # scratch folder of --plot without a DIR


def add_arguments(parser) -> None:
    parser.add_argument("--clip", type=Path, default=Path("runs/bench-detections/clip"),
                        help="rendered clip folder (rendered there when it holds no clip.json)")
    parser.add_argument("--work", type=Path, default=Path("runs/bench-detections"), help="run folders go here")
    parser.add_argument("--frames", type=int, default=250, help="clip length when rendering (default 250)")
    parser.add_argument("--preset", default="main", help="synth preset when rendering (default main)")
    parser.add_argument("--seed", type=int, default=3, help="synth seed when rendering (default 3)")
    parser.add_argument("--width", type=int, default=1920, help="clip width when rendering (default 1920)")
    parser.add_argument("--height", type=int, default=1080, help="clip height when rendering (default 1080)")
    parser.add_argument("--experiments", nargs="+", choices=("files", "keypoints"), default=["files", "keypoints"])
    parser.add_argument("--lag", type=int, default=TrackingConfig.lag_frames,
                        help=f"fixed-lag smoother lag in frames (default {TrackingConfig.lag_frames})")
    parser.add_argument("--no-direct-fixed-lag", action="store_true",
                        help="files: skip the fixed-lag run on the frames directly (the slowest run)")
    parser.add_argument("--kp-noise-px", type=float, default=5.0, help="keypoints: noise sigma per axis, px (default 5)")
    parser.add_argument("--kp-mislabel", type=float, default=0.1, help="keypoints: share mislabelled (default 0.1)")
    parser.add_argument("--kp-gross-px", type=float, default=50.0,
                        help="keypoints: a per-frame fit whose mean marking error exceeds this is a gross failure; "
                             "jitter is also reported without those frames (default 50)")
    parser.add_argument("--kp-seed", type=int, default=0, help="keypoints: noise seed (default 0)")
    parser.add_argument("--plot", type=Path, nargs="?", default=None, const=DEFAULT_PLOT_DIR, metavar="DIR",
                        help=f"write the PNGs into DIR (--plot alone: the scratch folder {DEFAULT_PLOT_DIR}, "
                             "so that a run never overwrites the images kept in the repository)")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bars")


# --------------------------------------------------------------------------- helpers


def ensure_clip(args) -> dict:
    """The clip's clip.json, rendering the clip first when the folder has none."""
    from broadtrack_graph.synth.writer import read_clip_info, write_synthetic_clip

    if not (args.clip / "clip.json").is_file():
        log.info("rendering %d frames of %s into %s", args.frames, args.preset, args.clip)
        write_synthetic_clip(args.clip, args.preset, args.frames, args.width, args.height, args.seed,
                             progress=not args.no_progress)
    return read_clip_info(args.clip)


def score_run(result, annotations, width_px: int, height_px: int) -> dict:
    """SoccerNet metric (tau 5 and 10) and run figures of one RunResult."""
    from broadtrack_graph.metrics.soccernet import evaluate_cameras

    cameras = {r.frame_id: r.camera for r in result.records}
    report = evaluate_cameras(annotations, cameras, width_px, height_px, taus=(5.0, 10.0))
    statuses: dict[str, int] = {}
    for record in result.records:
        statuses[record.status] = statuses.get(record.status, 0) + 1
    no_detection_notes = sum(1 for r in result.records if r.reason and "no detections" in r.reason)
    summary = result.summary or {}
    return {
        "jac5": report["taus"]["5"]["accuracy"], "jac10": report["taus"]["10"]["accuracy"],
        "final_score5": report["taus"]["5"]["final_score"], "completeness": report["completeness"],
        "mre5_px": report["taus"]["5"]["mre_px"], "medre5_px": report["taus"]["5"]["medre_px"],
        "frames": len(result.records), "statuses": statuses,
        "frames_noted_without_detections": no_detection_notes,
        "fps": summary.get("fps"), "per_frame_mre": {k: v["mre_px"] for k, v in report["per_frame"].items()},
    }


def noisy_keypoint_records(keypoints_by_frame: list[dict], frame_ids: list[str], width_px: int, height_px: int,
                           pitch, noise_px: float, mislabel: float, seed: int) -> tuple[list[dict], dict]:
    """Detections-file records of noisy, partly mislabelled keypoints (see the module docstring).

    Args:
        keypoints_by_frame: per frame {template keypoint name: (2,) true pixels}.
    Returns:
        (records, counts) with counts of keypoints written and mislabelled.
    """
    rng = np.random.default_rng(seed)
    all_names = sorted(pitch.keypoints)
    records, written, wrong = [], 0, 0
    for index, (frame_id, keypoints) in enumerate(zip(frame_ids, keypoints_by_frame)):
        names = sorted(keypoints)
        entries = []
        used = set(names)  # a wrong name is one the frame does not hold yet (else the reader drops a duplicate)
        for name in names:
            uv = np.asarray(keypoints[name], float) + rng.normal(0.0, noise_px, 2)
            label = name
            if rng.random() < mislabel:
                others = [n for n in all_names if n not in used]
                label = others[rng.integers(len(others))]
                used.add(label)
                wrong += 1
            entries.append((label, round(float(uv[0]), 2), round(float(uv[1]), 2), 0.9))
            written += 1
        records.append(named_keypoints_record(index, frame_id, (width_px, height_px), entries))
    return records, {"keypoints": written, "mislabelled": wrong}


def _jitters(states_by_name: dict[str, np.ndarray], frames: np.ndarray) -> dict:
    from broadtrack_graph.metrics.compare import jitter

    out = {}
    for name, states in states_by_name.items():
        out[name] = {"pan_deg": jitter(np.degrees(states[:, 2]), frames, wrap_deg=True)["rms_d1"],
                     "focal_px": jitter(states[:, 0], frames)["rms_d1"]}
    return out


# --------------------------------------------------------------------------- experiments


def run_files(args, info: dict, plot_dir: Path | None) -> dict:
    """Experiment 1: detect -> file -> track (file alone, file + frames, frames directly)."""
    from broadtrack_graph.actions.detect import export_detections, import_annotations
    from broadtrack_graph.actions.track import track_input
    from broadtrack_graph.io.annotations import read_annotations

    W, H = int(info["width_px"]), int(info["height_px"])
    annotations = read_annotations(args.clip / "annotations")
    work = args.work / "files"
    progress = not args.no_progress
    detections = work / "detections.jsonl"
    timings = {}
    started = time.perf_counter()
    export = export_detections(args.clip, detections, TrackingConfig(mode="online"), track_dir=work / "frames-online",
                               progress=progress)
    timings["detect_s"] = time.perf_counter() - started
    runs = {"frames-online (naming run of detect)": export.track}
    plans = [("file-online", "online", None), ("file-fixed-lag", "fixed-lag", None), ("file-batch", "batch", None),
             ("file+frames-online", "online", args.clip), ("file+frames-fixed-lag", "fixed-lag", args.clip)]
    for name, mode, frames in plans:
        started = time.perf_counter()
        runs[name] = track_input(frames, work / name, TrackingConfig(mode=mode, lag_frames=args.lag),
                                 detections_path=detections, progress=progress)
        timings[f"{name}_s"] = time.perf_counter() - started
    if not args.no_direct_fixed_lag:
        started = time.perf_counter()
        runs["frames-fixed-lag"] = track_input(args.clip, work / "frames-fixed-lag",
                                               TrackingConfig(mode="fixed-lag", lag_frames=args.lag), progress=progress)
        timings["frames-fixed-lag_s"] = time.perf_counter() - started
    imported = import_annotations(args.clip / "annotations", work / "annotations.jsonl", W, H)
    for name, mode in (("annotations-online", "online"), ("annotations-fixed-lag", "fixed-lag")):
        started = time.perf_counter()
        runs[name] = track_input(None, work / name, TrackingConfig(mode=mode, lag_frames=args.lag),
                                 detections_path=work / "annotations.jsonl", progress=progress)
        timings[f"{name}_s"] = time.perf_counter() - started
    scores = {name: score_run(result, annotations, W, H) for name, result in runs.items()}
    if plot_dir is not None:
        _plot_files(scores, plot_dir / "detections_files.png", info)
    for score in scores.values():
        score.pop("per_frame_mre")
    return {"clip": str(args.clip), "resolution": [W, H], "detections_file": str(detections),
            "export": export.to_dict(), "annotations_import": imported.to_dict(),
            "runs": scores, "timings_s": {k: round(v, 2) for k, v in timings.items()}}


def run_keypoints(args, info: dict, plot_dir: Path | None) -> dict:
    """Experiment 2: keypoints only, smoothed track vs fitting each frame alone."""
    from broadtrack_graph.actions.track import track_input
    from broadtrack_graph.benchmarks.template_error import template_errors_px
    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.io.detections import read_detections
    from broadtrack_graph.io.detections_writer import DetectionsWriter
    from broadtrack_graph.io.jsonfile import read_json
    from broadtrack_graph.reinit.keypoints import reinit_from_keypoints
    from broadtrack_graph.synth.writer import read_camera_track, read_keypoints_file
    from broadtrack_graph.track.config import TrackingConfig

    W, H = int(info["width_px"]), int(info["height_px"])
    pitch = PitchTemplate()
    truth = read_camera_track(args.clip / "cameras", W, H)
    frame_ids = [entry["frame_id"] for entry in read_json(args.clip / "ground_truth.json")["frames"]][:len(truth)]
    keypoints = [read_keypoints_file(args.clip / "keypoints" / f"{fid}.json") for fid in frame_ids]
    records, counts = noisy_keypoint_records(keypoints, frame_ids, W, H, pitch, args.kp_noise_px, args.kp_mislabel,
                                             args.kp_seed)
    work = args.work / "keypoints"
    work.mkdir(parents=True, exist_ok=True)
    path = work / "keypoints.jsonl"
    with DetectionsWriter(path) as writer:
        for record in records:
            writer.write_record(record)
    progress = not args.no_progress
    estimates: dict[str, list] = {}
    timings = {}
    for name, mode in (("online", "online"), ("fixed-lag", "fixed-lag"), ("batch", "batch")):
        started = time.perf_counter()
        result = track_input(None, work / name, TrackingConfig(mode=mode, lag_frames=args.lag), detections_path=path,
                             progress=progress)
        timings[f"{name}_s"] = time.perf_counter() - started
        by_index = {r.frame_index: r.camera for r in result.records}
        estimates[name] = [by_index.get(i) for i in range(len(truth))]
    # Per-frame baseline: exactly what the reader hands the tracker, fitted frame by frame.
    read = read_detections(path, pitch)
    started = time.perf_counter()
    single = []
    for index in range(len(truth)):
        kp = read.frames[index].keypoints if index in read.frames else None
        if kp is None or len(kp) < 2:
            single.append(None)
            continue
        single.append(reinit_from_keypoints(kp.uv_px, kp.points_w, W, H).camera)
    timings["per-frame_s"] = time.perf_counter() - started
    estimates = {"per-frame": single, **estimates}

    points_w = np.vstack(list(pitch.sample_uniform(1.0).values()))
    common = [i for i in range(len(truth)) if all(est[i] is not None for est in estimates.values())]
    frames = np.array(common)
    figures = {}
    per_frame_error = {}
    for name, cams in estimates.items():
        errors = [template_errors_px(cams[i], truth[i], points_w) for i in common]
        pooled = np.concatenate([e for e in errors if len(e)]) if errors else np.zeros(0)
        means = np.array([np.mean(e) if len(e) else np.nan for e in errors])
        per_frame_error[name] = means
        states = np.array([cams[i].to_vector() for i in common]).reshape(-1, 8)
        figures[name] = {
            "frames_with_camera": int(sum(c is not None for c in cams)),
            "median_error_px": float(np.median(pooled)) if len(pooled) else None,
            "median_frame_mean_error_px": float(np.nanmedian(means)) if len(means) else None,
            "p90_frame_mean_error_px": float(np.nanpercentile(means, 90)) if len(means) else None,
            **{f"jitter_{k}": v for k, v in _jitters({name: states}, frames)[name].items()},
        }
    true_states = np.array([truth[i].to_vector() for i in common]).reshape(-1, 8)
    figures["truth"] = {f"jitter_{k}": v for k, v in _jitters({"truth": true_states}, frames)["truth"].items()}
    # RMS jitter is dominated by the per-frame fit's gross failures: also over the frames without them.
    sane = per_frame_error["per-frame"] < args.kp_gross_px
    for name, cams in list(estimates.items()) + [("truth", truth)]:
        states = np.array([cams[i].to_vector() for i in common]).reshape(-1, 8)[sane]
        for key, value in _jitters({name: states}, frames[sane])[name].items():
            figures[name][f"jitter_{key}_without_gross"] = value
    figures["per-frame"]["gross_failures"] = int((~sane).sum())
    base = figures["per-frame"]
    checks = {}
    for name in ("fixed-lag", "batch"):
        f = figures[name]
        checks[name] = {
            "error_reduction": 1.0 - f["median_error_px"] / base["median_error_px"],
            "pan_jitter_ratio": base["jitter_pan_deg"] / f["jitter_pan_deg"],
            "focal_jitter_ratio": base["jitter_focal_px"] / f["jitter_focal_px"],
        }
        checks[name]["pan_jitter_ratio_without_gross"] = base["jitter_pan_deg_without_gross"] / f["jitter_pan_deg_without_gross"]
        checks[name]["focal_jitter_ratio_without_gross"] = (base["jitter_focal_px_without_gross"]
                                                            / f["jitter_focal_px_without_gross"])
        checks[name]["pass"] = bool(checks[name]["error_reduction"] >= 0.3 and checks[name]["pan_jitter_ratio"] >= 3
                                    and checks[name]["focal_jitter_ratio"] >= 3)
    if plot_dir is not None:
        _plot_keypoints(estimates, truth, common, per_frame_error, plot_dir / "detections_keypoints.png", args)
    return {"clip": str(args.clip), "resolution": [W, H], "file": str(path), "noise_px": args.kp_noise_px,
            "mislabel_share": args.kp_mislabel, **counts, "reader_issues": len(read.issues),
            "frames": len(truth), "frames_compared": len(common), "figures": figures, "smoothed_vs_per_frame": checks,
            "timings_s": {k: round(v, 2) for k, v in timings.items()}}


# --------------------------------------------------------------------------- pictures


def _plot_files(scores: dict, path: Path, info: dict) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path.parent.mkdir(parents=True, exist_ok=True)
    fig, (ax_bar, ax_frames) = plt.subplots(1, 2, figsize=(15, 5), gridspec_kw={"width_ratios": [1, 1.6]})
    names = list(scores)
    y = np.arange(len(names))
    ax_bar.barh(y - 0.2, [scores[n]["jac5"] * 100 for n in names], 0.4, label="JaC@5")
    ax_bar.barh(y + 0.2, [scores[n]["jac10"] * 100 for n in names], 0.4, label="JaC@10")
    ax_bar.axvline(80, color="k", lw=0.8, ls="--")
    ax_bar.set_yticks(y, names, fontsize=8)
    ax_bar.invert_yaxis()
    ax_bar.set_xlabel("%")
    ax_bar.set_xlim(0, 100)
    ax_bar.legend(loc="upper center", bbox_to_anchor=(0.5, -0.1), ncol=2)
    ax_bar.set_title(f"{info.get('preset')} clip {info['width_px']}x{info['height_px']}, {info.get('frames_written')} frames")
    for name in names:
        per = scores[name]["per_frame_mre"]
        ids = sorted(per)
        ax_frames.plot([int(i) for i in ids], [np.nan if per[i] is None else per[i] for i in ids], lw=0.8, label=name)
    ax_frames.set_xlabel("frame id")
    ax_frames.set_yscale("log")
    ax_frames.set_ylabel("mean distance of annotated points to the projected class (px)")
    ax_frames.legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _plot_keypoints(estimates: dict, truth: list, common: list, per_frame_error: dict, path: Path, args) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    path.parent.mkdir(parents=True, exist_ok=True)
    fig, axes = plt.subplots(3, 1, figsize=(13, 10), sharex=True)
    frames = np.arange(len(truth))
    t_states = np.array([c.to_vector() for c in truth])
    axes[0].plot(frames, (np.degrees(t_states[:, 2]) + 180.0) % 360.0 - 180.0, "k", lw=1.5, label="truth")
    axes[1].plot(frames, t_states[:, 0], "k", lw=1.5, label="truth")
    for name, cams in estimates.items():
        pan = np.array([np.nan if c is None else (np.degrees(c.pan_rad) + 180.0) % 360.0 - 180.0 for c in cams])
        focal = np.array([np.nan if c is None else c.focal_px for c in cams])
        style = {"lw": 0.8, "alpha": 0.8} if name == "per-frame" else {"lw": 1.1}
        axes[0].plot(frames, pan, label=name, **style)
        axes[1].plot(frames, focal, label=name, **style)
        axes[2].plot(common, per_frame_error[name], label=name, **style)
    axes[0].set_ylabel("pan (deg)")
    axes[1].set_ylabel("focal (px)")
    axes[2].set_ylabel("mean marking error (px)")
    axes[2].set_yscale("log")
    axes[2].set_xlabel("frame")
    axes[0].set_title(f"keypoints only: {args.kp_noise_px:g} px noise, {100 * args.kp_mislabel:g} % mislabelled")
    axes[0].legend(ncol=5, fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# --------------------------------------------------------------------------- entry


def run(args) -> dict:
    import cv2

    cv2.setNumThreads(1)
    info = ensure_clip(args)
    plot_dir = args.plot
    report: dict = {"clip_info": {k: info.get(k) for k in ("preset", "seed", "width_px", "height_px", "frames_written")}}
    if "files" in args.experiments:
        report["files"] = run_files(args, info, plot_dir)
    if "keypoints" in args.experiments:
        report["keypoints"] = run_keypoints(args, info, plot_dir)
    return report
