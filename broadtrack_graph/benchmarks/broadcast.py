"""``broadtrack-graph bench broadcast``: whole broadcasts, many shots of several cameras.

Synthetic part: the ``broadcast`` clip (:mod:`broadtrack_graph.synth.broadcast`: hard cuts
between the main camera, a high camera behind a goal, a low camera on the 16 m line,
close-ups and crowd shots; default 1500 frames at 1920x1080, seed 0) is rendered once under
``--out``/clips (reused when complete) and tracked in every ``--modes`` mode with the
weight-free detector (:func:`~broadtrack_graph.benchmarks.clips.track_clip`, as ``bench
accuracy`` does). Per mode (the scoring rules: :mod:`broadtrack_graph.metrics.broadcast`):

* ``fps``: frames / wall seconds of the tracking call; ``reinit_time_share``: summary
  ``timings_s.reinit_s`` (a batch run's first pass) / that wall time; ``status_counts`` from
  track.jsonl;
* ``cuts``: true cuts found within 2 frames by the run's shots.json boundaries;
* ``shot_kinds``: per true shot, the predicted kind most of its frames got, by group (pitch:
  "main", "other-camera"; no-pitch: "close-up", "crowd") and exactly;
* ``camera_ids``: true camera -> the predicted id most of its frames got, one-to-one or not,
  the share of pitch frames whose predicted id belongs to their camera (a track.jsonl line
  without ``camera_id`` counts as "main" when it has a camera);
* ``by_kind``: the SoccerNet metric (:func:`~broadtrack_graph.metrics.soccernet.evaluate_cameras`,
  at the clip's resolution) against the clip's annotations over the frames of the true
  "main" shots and of the true "other-camera" shots: JaC@5, JaC@10, completeness, MRE;
* ``cameras_on_no_pitch_frames``: cameras written on close-up / crowd frames (should be 0);
* ``tripods``: per true camera, the run's tripod of the id it maps to against the truth
  (a single-tripod tripod.json counts as camera "main").

Real part (``--video-dir DIR``): :mod:`broadtrack_graph.benchmarks.broadcast_real`.

The report: {"synthetic": {"clip", "truth" (shots, cameras), "modes": {mode: figures}},
"real": {...} or None}; a short table goes to stderr.
"""

from __future__ import annotations

import logging
import sys
import time
from collections import Counter
from pathlib import Path

from broadtrack_graph.benchmarks.options import add_reinit_model, tracker_options
from broadtrack_graph.track.config import TrackingConfig

HELP = ("whole broadcasts: cuts, shot kinds, camera ids and per-camera accuracy on a rendered multi-camera clip; "
        "a splice of real videos (--video-dir)")

log = logging.getLogger(__name__)

CUT_TOLERANCE_FRAMES = 2
TAUS_PX = (5.0, 10.0)


def add_arguments(parser) -> None:
    from broadtrack_graph.types.modes import MODES

    parser.add_argument("--frames", type=int, default=1500, help="frames of the synthetic clip (default 1500)")
    parser.add_argument("--width", type=int, default=1920, help="synthetic clip width (default 1920)")
    parser.add_argument("--height", type=int, default=1080, help="synthetic clip height (default 1080)")
    parser.add_argument("--seed", type=int, default=0, help="synthetic clip seed (default 0)")
    parser.add_argument("--modes", nargs="+", default=list(MODES), choices=MODES,
                        help="tracking modes (default online fixed-lag batch)")
    parser.add_argument("--lag", type=int, default=TrackingConfig.lag_frames,
                        help=f"fixed-lag smoother lag in frames (default {TrackingConfig.lag_frames})")
    parser.add_argument("--no-synthetic", action="store_true", help="skip the synthetic part")
    add_reinit_model(parser)
    parser.add_argument("--video-dir", type=Path, default=None,
                        help="real part: splice the *.mp4 videos of this folder with hard cuts and track it online")
    parser.add_argument("--segment-frames", type=int, default=120, help="real part: typical segment length (default 120)")
    parser.add_argument("--segments", type=int, default=6, help="real part: number of segments (default 6)")
    parser.add_argument("--real-height", type=int, default=720, help="real part: splice height (default 720)")
    parser.add_argument("--real-width", type=int, default=None,
                        help="real part: splice width (default 16:9 of --real-height: 1280 at 720, 1920 at 1080); a "
                             "width off that shape stretches the frames, which no pinhole camera fits")
    parser.add_argument("--out", type=Path, default=Path("bench-broadcast"),
                        help="folder for clips/, runs/ and real/ (default ./bench-broadcast); a complete rendered "
                             "clip found there is reused")
    parser.add_argument("--reuse-runs", action="store_true",
                        help="also reuse finished runs whose configuration matches (default: track again)")
    parser.add_argument("--threads", type=int, default=1, help="OpenCV threads (default 1)")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bars")


# --------------------------------------------------------------------------- synthetic part


def ensure_broadcast_clip(clips_dir: Path, frames: int, width_px: int, height_px: int, seed: int,
                          progress: bool = True) -> tuple[Path, bool]:
    """The rendered broadcast clip (reused when complete with its truth files); (folder, rendered now)."""
    from broadtrack_graph.benchmarks.clips import clip_folder_name, ensure_clip
    from broadtrack_graph.io.broadcast_truth import has_broadcast_truth
    from broadtrack_graph.synth.broadcast import BROADCAST_PRESET
    from broadtrack_graph.synth.writer import write_synthetic_clip

    folder, rendered = ensure_clip(clips_dir, BROADCAST_PRESET, frames, width_px, height_px, seed, progress)
    if not has_broadcast_truth(folder):
        write_synthetic_clip(clips_dir / clip_folder_name(BROADCAST_PRESET, frames, width_px, height_px, seed),
                             preset=BROADCAST_PRESET, frame_count=frames, width_px=width_px, height_px=height_px,
                             seed=seed, progress=progress)
        rendered = True
    return folder, rendered


def group_metrics(annotations, cameras: dict, frame_ids: list[str], width_px: int, height_px: int) -> dict:
    """SoccerNet JaC@5 / JaC@10 / completeness / MRE over the annotated frames among ``frame_ids``.

    Args:
        annotations: the clip's AnnotationSet; cameras: frame id -> Camera or None (the run's).
        frame_ids: the frames of the group; width_px, height_px: evaluation resolution.
    """
    from broadtrack_graph.io.annotations import AnnotationSet
    from broadtrack_graph.metrics.soccernet import evaluate_cameras

    subset = AnnotationSet(frames={f: annotations.frames[f] for f in frame_ids if f in annotations.frames})
    if not subset.frames:
        return {"frames": len(frame_ids), "annotated_frames": 0, "jac_5": None, "jac_10": None,
                "completeness": None, "mre_px": None}
    result = evaluate_cameras(subset, cameras, width_px, height_px, taus=TAUS_PX)
    with_camera = result["frames_with_camera"]
    jac = {tau: result["taus"][tau]["accuracy"] if with_camera else None for tau in ("5", "10")}
    return {"frames": len(frame_ids), "annotated_frames": result["frames"], "frames_with_camera": with_camera,
            "jac_5": None if jac["5"] is None else round(jac["5"], 4),
            "jac_10": None if jac["10"] is None else round(jac["10"], 4),
            "completeness": round(result["completeness"], 4),
            "mre_px": None if result["mre_px"] is None else round(result["mre_px"], 3)}


def score_broadcast_run(run_dir: Path, truth, annotations, width_px: int, height_px: int, tracked: dict) -> dict:
    """The figures of one run of the broadcast clip (module docstring).

    Args:
        run_dir: the run folder; truth: the clip's BroadcastTruth; annotations: its AnnotationSet.
        width_px, height_px: the clip's size; tracked: :func:`~broadtrack_graph.benchmarks.clips.track_clip`'s result.
    """
    from broadtrack_graph.benchmarks.clips import stage_timings
    from broadtrack_graph.io.run_folder import RunFolder, read_frame_camera_ids
    from broadtrack_graph.io.shots_file import SHOTS_FILE, read_shots
    from broadtrack_graph.io.tripod_file import read_tripods_by_camera
    from broadtrack_graph.metrics.broadcast import (
        camera_id_scores,
        cut_scores,
        frame_kinds,
        frames_by_kind,
        kind_scores,
        tripod_scores,
    )
    from broadtrack_graph.synth.clip import frame_id

    folder = RunFolder(run_dir)
    frame_count = len(truth.camera_ids)
    if not folder.has_track():
        return {"error": tracked.get("error") or "no track.jsonl", "frames": frame_count}
    track = folder.read_track(width_px, height_px)
    records = {r.frame_index: r for r in track.records}
    ids = read_frame_camera_ids(run_dir)
    predicted_ids = [ids.get(i) if i in records and records[i].camera is not None else None for i in range(frame_count)]
    predicted_shots = read_shots(run_dir / SHOTS_FILE) if (run_dir / SHOTS_FILE).is_file() else []
    cameras = {r.frame_id: r.camera for r in track.records}
    id_scores = camera_id_scores(truth.camera_ids, predicted_ids)
    run_tripods = read_tripods_by_camera(folder.tripod_path) if folder.has_tripod() else {}
    wall_s = tracked.get("wall_s")
    reinit_s = stage_timings(track.summary).get("reinit_s")
    return {
        "error": tracked.get("error"),
        "frames": frame_count,
        "frames_written": len(records),
        "wall_s": wall_s,
        "fps": round(frame_count / wall_s, 2) if wall_s else None,
        "reinit_time_share": round(reinit_s / wall_s, 4) if wall_s and reinit_s is not None else None,
        "status_counts": dict(Counter(r.status for r in track.records)),
        "cuts": cut_scores(truth.shots, predicted_shots, CUT_TOLERANCE_FRAMES),
        "predicted_shots": [[s.start, s.end, s.kind, s.camera_id] for s in predicted_shots],
        "shot_kinds": kind_scores(truth.shots, frame_kinds(predicted_shots, frame_count)),
        "camera_ids": id_scores,
        "by_kind": {kind: group_metrics(annotations, cameras, [frame_id(i) for i in frames], width_px, height_px)
                    for kind, frames in frames_by_kind(truth.shots).items()},
        "cameras_on_no_pitch_frames": sum(1 for i, cid in enumerate(truth.camera_ids)
                                          if cid is None and i in records and records[i].camera is not None),
        "tripods": tripod_scores(truth.tripods, run_tripods, id_scores["mapping"]),
        "reused_run": tracked.get("reused"),
    }


def synthetic_section(args, out: Path, progress: bool) -> dict:
    """Render or reuse the clip, track it per mode, score every run."""
    from broadtrack_graph.benchmarks.clips import track_clip
    from broadtrack_graph.io.annotations import read_annotations
    from broadtrack_graph.io.broadcast_truth import read_broadcast_truth

    started = time.perf_counter()
    clip, rendered = ensure_broadcast_clip(out / "clips", args.frames, args.width, args.height, args.seed, progress)
    truth = read_broadcast_truth(clip)
    annotations = read_annotations(clip)
    section = {
        "clip": {"path": str(clip), "frames": args.frames, "width_px": args.width, "height_px": args.height,
                 "seed": args.seed, "rendered_now": rendered,
                 "render_s": round(time.perf_counter() - started, 2) if rendered else None},
        "truth": {"shots": [[s.start, s.end, s.kind, s.camera_id] for s in truth.shots],
                  "cameras": sorted(truth.tripods),
                  "pitch_frames": sum(1 for c in truth.camera_ids if c is not None)},
        "modes": {},
    }
    for mode in args.modes:
        run_dir = out / "runs" / mode
        log.info("tracking the broadcast clip, %s", mode)
        tracked = track_clip(clip, run_dir, TrackingConfig(mode=mode, lag_frames=args.lag, **tracker_options(args)),
                              args.reuse_runs, progress)
        section["modes"][mode] = score_broadcast_run(run_dir, truth, annotations, args.width, args.height, tracked)
    return section


# --------------------------------------------------------------------------- the suite


def _fmt(value, digits: int = 3) -> str:
    return "-" if value is None else (f"{value:.{digits}g}" if isinstance(value, float) else str(value))


def summary_table(report: dict) -> str:
    """A few lines for a human (stderr): per mode and for the real splice."""
    lines = []
    synthetic = report.get("synthetic")
    if synthetic:
        lines.append(f"{'mode':<10} {'fps':>6} {'reinit':>7} {'cuts':>6} {'kinds grp/exact':>16} {'ids 1:1':>7} "
                     f"{'right':>6} {'main JaC@5':>10} {'other JaC@5':>11} {'no-pitch cams':>13}")
        for mode, m in synthetic["modes"].items():
            if "cuts" not in m:
                lines.append(f"{mode:<10} error: {m.get('error')}")
                continue
            by_kind, kinds = m["by_kind"], m["shot_kinds"]
            cuts = f"{m['cuts']['found']}/{m['cuts']['true_cuts']}"
            lines.append(
                f"{mode:<10} {_fmt(m['fps']):>6} {_fmt(m['reinit_time_share']):>7} {cuts:>6} "
                f"{_fmt(kinds['group_agreement']) + ' / ' + _fmt(kinds['exact_agreement']):>16} "
                f"{str(m['camera_ids']['one_to_one']):>7} {_fmt(m['camera_ids']['right_camera_share']):>6} "
                f"{_fmt(by_kind['main']['jac_5']):>10} {_fmt(by_kind['other-camera']['jac_5']):>11} "
                f"{m['cameras_on_no_pitch_frames']:>13}")
    real = report.get("real")
    if real:
        lines.append(f"real splice: {real['frames']} frames, {_fmt(real['fps'])} fps, reinit share "
                     f"{_fmt(real['reinit_time_share'])}, cuts {real['cuts']['found']}/{real['cuts']['true_cuts']}")
        for s in real["segments"]:
            lines.append(f"  {s['source']:<32} {s['start']:>5}-{s['end']:<5} with camera {s['frames_with_camera']:>4}"
                         f"  aligned {_fmt(s['aligned_share'])}  ids {s['camera_ids']}")
    return "\n".join(lines)


def run(args) -> dict:
    import cv2

    from broadtrack_graph.errors import InputError
    from broadtrack_graph.synth.broadcast import DEFAULT_PLAN

    if not args.no_synthetic and args.frames < 2 * len(DEFAULT_PLAN):
        raise InputError(None, f"--frames must be >= {2 * len(DEFAULT_PLAN)} (2 per shot of the plan), got {args.frames}")
    cv2.setNumThreads(int(args.threads))
    progress, out = not args.no_progress, Path(args.out)
    report: dict = {"out": str(out), "modes": list(args.modes), "synthetic": None, "real": None}
    if not args.no_synthetic:
        report["synthetic"] = synthetic_section(args, out, progress)
    if args.video_dir is not None:
        from broadtrack_graph.benchmarks.broadcast_real import real_section

        width = args.real_width if args.real_width is not None else splice_width(args.real_height)
        report["real"] = real_section(args.video_dir, out / "real", args.segment_frames, args.segments,
                                      width, args.real_height, progress, tracker_options(args))
    print(summary_table(report), file=sys.stderr)
    return report


def splice_width(height_px: int) -> int:
    """The width of a 16:9 frame ``height_px`` high (even, as video encoders want): 1280 at 720, 1920 at 1080."""
    return 2 * round(height_px * 16 / 9 / 2)
