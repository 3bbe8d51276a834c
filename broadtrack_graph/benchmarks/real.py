"""``broadtrack-graph bench real``: the tracker on real broadcast data, one section per data kind.

Sections (each a function ``section(args) -> dict | None``, listed in :data:`SECTIONS`; the
report merges them under their names; a section whose data is not given is skipped):

- ``tsworldcup`` (``--tsworldcup DIR``): for every clip folder in DIR holding
  ``detections.jsonl`` (a published detector's per-frame keypoints) and
  ``gt_homographies.json`` (per-frame ground-plane homographies), every requested mode is
  tracked from the detections file alone, and scored by the homography protocol
  (:mod:`broadtrack_graph.metrics.homography_protocol`: completeness, IoU_part with missing
  frames counted 0, IoU_whole, reprojection error, jitter) next to the per-frame baseline, a
  RANSAC homography fitted to each frame's keypoints alone. The ratios to the baseline and
  the targets (completeness 1.0, reprojection <= 0.8x, jitter <= 0.5x, IoU_part >= the
  baseline's) are reported per clip and mode.
- ``video`` (``--video-dir DIR``): every ``*.mp4`` in DIR tracked online end to end and scored
  by :mod:`broadtrack_graph.benchmarks.real_video` (frames with a camera, alignment with the
  visible lines measured without the tracker's detector, re-initialisations, other-view
  frames, cuts, fps, stage timings, overlay videos). With ``--shadow KEPT``, each clip under a
  stand's shadow keeping that share of the light (:mod:`broadtrack_graph.benchmarks.shadow`); with ``--degrade
  W:Q:N``, as a lower-league feed shows it (:mod:`broadtrack_graph.benchmarks.degrade`); with ``--zoom Z``, as a
  lens Z times longer shows it (:mod:`broadtrack_graph.benchmarks.zoom`); with ``--starts STEP``,
  also tracked from nothing from every STEP-th frame (:mod:`broadtrack_graph.benchmarks.real_starts`).

Runs are written under ``--out`` (default ./bench-real); real data never belongs in the
repository. Wall times are of the whole run on the machine as it was (upper bounds on a
shared machine). OpenCV runs with ``--threads`` threads, by default those ``track`` gives a run
(:func:`~broadtrack_graph.track.feed.default_opencv_threads`): the fps are those a user's ``track`` gets.
"""

from __future__ import annotations

import logging
import time
from pathlib import Path

from broadtrack_graph.arguments import int_at_least, positive_share
from broadtrack_graph.benchmarks.degrade import parse_degradation
from broadtrack_graph.benchmarks.options import add_reinit_model
from broadtrack_graph.benchmarks.zoom import parse_zoom
from broadtrack_graph.types.modes import MODES

HELP = ("the tracker on real data: TS-WorldCup keypoint clips scored against their ground truth per mode vs a "
        "per-frame fit, and real broadcast videos (alignment, re-initialisations, other views, cuts, fps)")

log = logging.getLogger(__name__)

TARGETS = {"completeness": 1.0, "reprojection_ratio_max": 0.8, "jitter_ratio_max": 0.5, "iou_part_ratio_min": 1.0}
"""Targets against the per-frame baseline (ratios = mode / baseline)."""


def add_arguments(parser) -> None:
    parser.add_argument("--tsworldcup", type=Path, default=None,
                        help="folder of TS-WorldCup clips (each with detections.jsonl and gt_homographies.json)")
    parser.add_argument("--modes", nargs="+", default=list(MODES), choices=MODES, help="tracking modes (default all)")
    parser.add_argument("--clips", nargs="+", default=None, help="only these clip folder names")
    parser.add_argument("--out", type=Path, default=Path("bench-real"), help="folder for the runs (default ./bench-real)")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bars")
    parser.add_argument("--video-dir", type=Path, default=None, help="folder of real broadcast videos (*.mp4)")
    parser.add_argument("--threads", type=int_at_least(1), default=None, metavar="N",
                        help="OpenCV threads (default: as `track`, the cores the tracking and decoding threads leave, "
                             "at least 1)")
    add_reinit_model(parser)
    parser.add_argument("--runs", type=Path, default=None,
                        help="video: score existing run folders <RUNS>/<clip> instead of tracking again")
    parser.add_argument("--end", type=int, default=None, help="video: track only the first END frames of each clip")
    parser.add_argument("--score-every", type=int, default=1, help="video: score the alignment of every Nth frame")
    parser.add_argument("--no-overlay", action="store_true", help="video: do not write overlay videos")
    parser.add_argument("--shadow", type=positive_share, default=None, metavar="KEPT",
                        help="video: track each clip under a stand's shadow laid over the right of its frames, keeping "
                             "this share of the light (0.45: a sunny afternoon), and score the cameras on the unshaded "
                             "frames")
    parser.add_argument("--starts", type=int_at_least(1), default=None, metavar="STEP",
                        help="video: also track each clip from nothing from every STEP-th frame (a shot cut into "
                             "there) and report how soon a camera is found and whether it is aligned")
    parser.add_argument("--start-frames", type=int_at_least(1), default=15, metavar="N",
                        help="video, with --starts: frames tracked from each start (default 15)")
    parser.add_argument("--degrade", type=parse_degradation, default=None, metavar="W:Q:N",
                        help="video: track each clip as a lower-league feed or a web stream shows it, reduced to W "
                             "pixels wide with noise of N grey levels and JPEG quality Q (854:25:3, say), and score "
                             "the cameras on the original frames (with --shadow: shaded first)")
    parser.add_argument("--zoom", type=parse_zoom, default=None, metavar="Z",
                        help="video: track each clip as a lens Z times longer shows it (each frame's centre, 1/Z of "
                             "its width and height, its pixels kept) and score the cameras on those zoomed frames "
                             "(with --shadow: shaded first; with --degrade: zoomed first); the clip is tracked on its "
                             "whole frames too (with --runs: read from RUNS/<clip>) to count the zoomed frames whose "
                             "markings fix a camera")


def tsworldcup_section(args) -> dict | None:
    """The TS-WorldCup section: per clip, the baseline and each mode's protocol figures."""
    if args.tsworldcup is None:
        return None
    from broadtrack_graph.errors import InputError

    root = Path(args.tsworldcup)
    clips = sorted(p for p in root.iterdir() if (p / "detections.jsonl").is_file()
                   and (p / "gt_homographies.json").is_file()) if root.is_dir() else []
    if args.clips:
        clips = [p for p in clips if p.name in set(args.clips)]
    if not clips:
        raise InputError(root, "no clip folder with detections.jsonl and gt_homographies.json")
    section = {"root": str(root), "targets": TARGETS, "clips": {}}
    for clip in clips:
        section["clips"][clip.name] = score_tsworldcup_clip(clip, args.modes, Path(args.out) / "tsworldcup" / clip.name,
                                                            not args.no_progress)
    section["all_targets_met"] = all(m["meets_targets"] for c in section["clips"].values() for m in c["modes"].values())
    return section


def score_tsworldcup_clip(clip: Path, modes, out_dir: Path, progress: bool = False) -> dict:
    """Baseline and every mode on one clip folder; the runs go to out_dir/<mode>."""
    from broadtrack_graph.actions.track import track_input
    from broadtrack_graph.io.detections import read_detections
    from broadtrack_graph.io.gt_homographies import read_gt_homographies
    from broadtrack_graph.io.run_folder import read_track
    from broadtrack_graph.metrics.homography_protocol import clip_figures, fit_keypoint_homography
    from broadtrack_graph.track.config import TrackingConfig

    gt = read_gt_homographies(clip / "gt_homographies.json")
    width, height = gt.image_size
    detections = read_detections(clip / "detections.jsonl")
    baseline = {}
    for index, obs in detections.frames.items():
        kp = obs.keypoints
        baseline[index] = None if kp is None else fit_keypoint_homography(kp.uv_px, kp.points_w[:, :2])
    base = clip_figures(baseline, gt.homographies, width, height)
    result = {"frames": len(gt.homographies), "baseline_per_frame_homography": _rounded(base), "modes": {}}
    for mode in modes:
        run_dir = out_dir / mode
        started = time.perf_counter()
        track_input(None, run_dir, TrackingConfig(mode=mode), detections_path=clip / "detections.jsonl",
                    progress=progress)
        wall_s = time.perf_counter() - started
        track = read_track(run_dir, width, height)
        cameras = {r.frame_index: r.camera for r in track.records}
        figures = clip_figures(cameras, gt.homographies, width, height)
        ratios = {
            "reprojection": _ratio(figures["reprojection_px"], base["reprojection_px"]),
            "jitter": _ratio(figures["jitter_px"], base["jitter_px"]),
            "iou_part": _ratio(figures["iou_part"], base["iou_part"]),
        }
        meets = (figures["completeness"] >= TARGETS["completeness"]
                 and ratios["reprojection"] is not None and ratios["reprojection"] <= TARGETS["reprojection_ratio_max"]
                 and ratios["jitter"] is not None and ratios["jitter"] <= TARGETS["jitter_ratio_max"]
                 and ratios["iou_part"] is not None and ratios["iou_part"] >= TARGETS["iou_part_ratio_min"])
        result["modes"][mode] = {**_rounded(figures), "vs_baseline": _rounded(ratios), "meets_targets": bool(meets),
                                 "reinitialisations": track.summary.get("reinitialisations"),
                                 "wall_s": round(wall_s, 2), "run": str(run_dir)}
        log.info("%s %s: %s", clip.name, mode, result["modes"][mode])
    return result


def video_section(args) -> dict | None:
    """Real broadcast videos (``--video-dir``), runs under ``--out``/video."""
    from argparse import Namespace

    from broadtrack_graph.benchmarks import real_video

    if args.video_dir is None:
        return None
    video_args = Namespace(**{**vars(args), "out": Path(args.out) / "video"})
    if not real_video.has_video_data(video_args):
        from broadtrack_graph.errors import InputError

        raise InputError(args.video_dir, "no *.mp4 video in this folder")
    return real_video.run_video_clips(video_args)


SECTIONS = {"tsworldcup": tsworldcup_section, "video": video_section}
"""Section name -> function(args) -> dict or None (skipped). Other real-data sections are added here."""


def run(args) -> dict:
    import cv2

    from broadtrack_graph.track.feed import default_opencv_threads

    report: dict = {"sections": {}}
    threads = cv2.getNumThreads()
    cv2.setNumThreads(int(getattr(args, "threads", None) or default_opencv_threads()))
    report["opencv_threads"] = cv2.getNumThreads()
    try:
        for name, section in SECTIONS.items():
            figures = section(args)
            if figures is not None:
                report["sections"][name] = figures
    finally:
        cv2.setNumThreads(threads)
    if not report["sections"]:
        from broadtrack_graph.errors import InputError

        raise InputError(None, "bench real: give at least one data folder (--tsworldcup DIR and/or --video-dir DIR)")
    return report


def _ratio(value, reference):
    return None if value is None or not reference else value / reference


def _rounded(figures: dict) -> dict:
    return {k: (round(v, 4) if isinstance(v, float) else v) for k, v in figures.items()}
