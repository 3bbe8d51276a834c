"""``broadtrack-graph bench players``: players on the pitch from each mode's cameras, against the true positions.

Synthetic part: a main-camera clip (default 200 frames at 1920x1080, rendered once into
``OUT/clips`` or reused; its ``players_pitch.json`` holds every player's true foot
position, written from the scene when an older clip lacks it) is tracked in each mode
(online, fixed-lag, batch) with the weight-free detector. The clip's ground-truth
player boxes (``Labels-GameState.json``) then go through each run's cameras
(:func:`broadtrack_graph.actions.players.players_from_run`), and through a per-frame
single-frame calibration: every frame re-initialised alone from its own detections
(:func:`broadtrack_graph.reinit.frame.reinitialise` at the default camera positions,
no tripod, no temporal link), as a per-frame calibrator does. Figures per source:

* position error (metres, bottom middle against the true foot): median, 95th
  percentile, split by the true horizontal distance from the camera (< 60 m, >= 60 m);
* distance covered per player (smoothed positions, :mod:`broadtrack_graph.metrics.players`)
  against the true distance over the same frames: median and worst |relative error|, and
  the total's inflation; the same for unsmoothed positions;
* the error of the ground-truth cameras themselves (the floor: box bottoms are not
  exactly the foot point);
* the weight-free detector's own player boxes on every fifth frame against the ground-truth boxes
  (:func:`detector_box_bottoms`: matched by IoU; how far each bottom, the foot point, is off, in shares
  of the player's height).

Real part (``--real VIDEO``, default the shared 720p clip when present): the clip is
tracked online and with the fixed-lag smoother, players from the detector's own blobs
(linked into tracks by IoU); the online run's boxes go through both runs' cameras and
the players' frame-to-frame jitter (second difference of positions over three frames)
is compared, and its part due to the cameras alone (each box's foot pixel held fixed
and put on the ground with the cameras of frames t-1, t, t+1).
A bird's-eye video is written to ``--real-out`` (never into the repository).
"""

from __future__ import annotations

import logging
import time
from pathlib import Path

import numpy as np

from broadtrack_graph.io.players_file import PLAYERS_FILE
from broadtrack_graph.io.run_folder import RunFolder

HELP = "players on the pitch: position error per mode and per-frame calibration, distance covered, real-clip jitter"

log = logging.getLogger(__name__)

NEAR_M = 60.0
"""Players closer than this (horizontal distance to the camera's focal point) form the 'near' group."""
REAL_CLIP = Path(__file__).resolve().parents[2].parent / "shared" / "data" / "real-video-dev" / "facup-wembley-720p.mp4"


def add_arguments(parser) -> None:
    from broadtrack_graph.track.config import TrackingConfig
    from broadtrack_graph.types.modes import MODES

    parser.add_argument("--frames", type=int, default=200, help="synthetic frames (default 200)")
    parser.add_argument("--seed", type=int, default=0, help="synthetic clip seed (default 0)")
    parser.add_argument("--width", type=int, default=1920)
    parser.add_argument("--height", type=int, default=1080)
    parser.add_argument("--modes", nargs="+", default=list(MODES), choices=MODES, help="tracking modes (default all)")
    parser.add_argument("--lag", type=int, default=TrackingConfig.lag_frames, help="fixed-lag smoother lag (frames)")
    parser.add_argument("--no-per-frame", action="store_true", help="skip the per-frame calibration (about 2 s a frame)")
    parser.add_argument("--out", type=Path, default=Path("bench-players"),
                        help="folder for clips/, runs/, players/ (default ./bench-players); clips found there are reused")
    parser.add_argument("--reuse-runs", action="store_true", help="reuse finished runs of the same configuration")
    parser.add_argument("--real", type=Path, default=REAL_CLIP if REAL_CLIP.is_file() else None,
                        help="real clip to track online and fixed-lag for the jitter (default the shared 720p clip "
                             "when present); 'none' to skip")
    parser.add_argument("--real-frames", type=int, default=None, help="real clip: frames to use (default all)")
    parser.add_argument("--real-out", type=Path, default=None,
                        help="real clip: folder for runs, players and the bird's-eye video (default OUT/real)")
    parser.add_argument("--no-progress", action="store_true", help="hide the progress bars")


# --------------------------------------------------------------------------- synthetic clip


def ensure_player_truth(clip: Path) -> Path:
    """The clip's ``players_pitch.json``, written from the (deterministic) scene when missing."""
    from broadtrack_graph.synth.clip import clip_scene
    from broadtrack_graph.synth.writer import PLAYER_TRUTH_FILE, read_clip_info, write_player_truth

    path = clip / PLAYER_TRUTH_FILE
    if not path.is_file():
        info = read_clip_info(clip)
        _, _, _, players = clip_scene(info["preset"], int(info["frames_written"]), int(info["width_px"]),
                                      int(info["height_px"]), int(info["seed"]))
        ids = sorted(p.stem for p in (clip / "img1").glob("*.jpg"))
        write_player_truth(clip, players, ids, float(info.get("fps", 25.0)))
    return path


def per_frame_run(clip: Path, run_dir: Path, progress: bool = True) -> dict:
    """Calibrate every frame alone (detector + re-initialisation) and write a run folder; returns timing."""
    import cv2
    from tqdm import tqdm

    from broadtrack_graph.detect.weightfree import WeightFreeDetector
    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.geometry.template import TemplateSampling, fitting_curves
    from broadtrack_graph.io.track_writer import TrackWriter
    from broadtrack_graph.reinit.frame import reinitialise
    from broadtrack_graph.types.status import FrameStatus
    from broadtrack_graph.types.track_record import TrackRecord

    pitch = PitchTemplate()
    detector = WeightFreeDetector(pitch)
    curves = fitting_curves(pitch)
    sampling = TemplateSampling(pitch)
    images = sorted((clip / "img1").glob("*.jpg"))
    first = cv2.imread(str(images[0]))
    height, width = first.shape[:2]
    started = time.perf_counter()
    failed = 0
    with TrackWriter(run_dir, width, height, run_info={"input": str(clip), "mode": "per-frame"}) as writer:
        for index, path in enumerate(tqdm(images, desc="per-frame", unit="frame", disable=not progress)):
            detections = detector.detect(cv2.imread(str(path)))
            result = reinitialise(detections.to_observations(index), detections, pitch, None, curves, sampling)
            if result.camera is None:
                failed += 1
                writer.write(TrackRecord(index, path.stem, index / 25.0, None, status=FrameStatus.FAILED,
                                         reason=result.reason or "no camera"))
            else:
                writer.write(TrackRecord(index, path.stem, index / 25.0, result.camera, status=FrameStatus.REINITIALISED,
                                         reinitialised=True))
    return {"wall_s": round(time.perf_counter() - started, 1), "failed_frames": failed}


def score_players(lines: list[dict], truth: dict, true_cameras: dict, fps: float, smooth_frames: int = 5) -> dict:
    """Position errors (split by distance) and distance covered against the truth, for one source's players.

    Args:
        lines: ``players.jsonl`` objects (track ids = the truth's).
        truth: ``players_pitch.json`` content.
        true_cameras: frame id -> the true camera (for the distance from the camera).
    """
    from broadtrack_graph.io.players_file import positions_from_lines
    from broadtrack_graph.metrics.players import AnalyticsConfig, error_stats, track_analytics

    positions = positions_from_lines(lines)
    true_xy = np.array([truth["frames"][fid].get(str(tid), [np.nan, np.nan])
                        for fid, tid in zip(positions.frame_ids, positions.track_id)], dtype=float).reshape(-1, 2)
    cam_xy = np.array([true_cameras[fid].position_m[:2] for fid in positions.frame_ids]).reshape(-1, 2)
    distance = np.linalg.norm(true_xy - cam_xy, axis=1)
    errors = np.linalg.norm(positions.xy_m - true_xy, axis=1)
    near = distance < NEAR_M
    report = {"all": error_stats(errors), f"near_lt_{int(NEAR_M)}m": error_stats(errors[near]),
              f"far_ge_{int(NEAR_M)}m": error_stats(errors[~near]),
              "boxes": len(positions), "located": int(positions.has_position.sum())}
    # Distance covered per player, on the frames where the source gave a position, against the truth there.
    has = positions.has_position
    for label, window in (("smoothed", smooth_frames), ("raw", 1)):
        config = AnalyticsConfig(fps=fps, smooth_frames=window)
        est = track_analytics(positions.frame[has], positions.track_id[has], positions.xy_m[has], config)
        ref = track_analytics(positions.frame[has], positions.track_id[has], true_xy[has], config)
        rel, est_total, ref_total = [], 0.0, 0.0
        for tid, values in est.items():
            if values["frames"] >= 2 * fps and ref[tid]["distance_m"] > 5.0:  # tracks seen 2 s or more, moving 5 m+
                rel.append(values["distance_m"] / ref[tid]["distance_m"] - 1.0)
                est_total += values["distance_m"]
                ref_total += ref[tid]["distance_m"]
        rel = np.array(rel)
        report[f"distance_{label}"] = {
            "tracks": int(len(rel)),
            "median_abs_rel_error_pct": None if not len(rel) else round(float(np.median(np.abs(rel))) * 100, 2),
            "max_abs_rel_error_pct": None if not len(rel) else round(float(np.max(np.abs(rel))) * 100, 2),
            "total_inflation_pct": None if ref_total <= 0 else round((est_total / ref_total - 1.0) * 100, 2),
        }
    return report


def camera_jitter_m(track, positions) -> np.ndarray:
    """Second differences (metres) of each box's foot pixel put on the ground with the cameras of frames t-1, t, t+1.

    The pixel is held fixed, so this is the part of the players' jitter that the cameras alone cause.

    Returns:
        (M,) norms, one per box whose frame and both neighbours have a camera.
    """
    from broadtrack_graph.geometry.ground import box_feet, ground_points

    cameras = {r.frame_index: r.camera for r in track.records}
    out = []
    for frame in np.unique(positions.frame):
        trio = [cameras.get(int(frame) + d) for d in (-1, 0, 1)]
        if any(c is None for c in trio):
            continue
        feet = box_feet(positions.box_px[positions.frame == frame])[:, 1]
        xy = [ground_points(c, feet)[0] for c in trio]
        out.append(np.linalg.norm(xy[2] - 2 * xy[1] + xy[0], axis=1))
    values = np.concatenate(out) if out else np.zeros(0)
    return values[np.isfinite(values)]


def _jitter_stats(values: np.ndarray) -> dict:
    if not len(values):
        return {"count": 0, "rms": None, "median": None, "p95": None}
    return {"count": int(len(values)), "rms": round(float(np.sqrt(np.mean(values ** 2))), 4),
            "median": round(float(np.median(values)), 4), "p95": round(float(np.percentile(values, 95)), 4)}


def _synthetic(args, progress: bool) -> dict:
    from broadtrack_graph.actions.players import PlayersOptions, players_from_run
    from broadtrack_graph.benchmarks.clips import ensure_clip, track_clip
    from broadtrack_graph.io.jsonfile import read_json
    from broadtrack_graph.io.player_boxes import read_player_boxes
    from broadtrack_graph.io.players_file import positions_from_lines
    from broadtrack_graph.io.run_folder import read_track
    from broadtrack_graph.metrics.players import all_jitter_m
    from broadtrack_graph.track.config import TrackingConfig

    out = Path(args.out)
    clip, rendered = ensure_clip(out / "clips", "main", args.frames, args.width, args.height, args.seed, progress)
    truth = read_json(ensure_player_truth(clip))
    fps = float(truth.get("fps", 25.0))
    boxes = read_player_boxes(clip)
    true_cameras = read_track(clip / "cameras").cameras
    options = PlayersOptions()
    report = {"clip": str(clip), "rendered_now": rendered, "frames": args.frames,
              "size": [args.width, args.height], "near_threshold_m": NEAR_M, "pixel_sigma_px": options.pixel_sigma_px,
              "boxes": boxes.box_count, "sources": {}}
    sources = {"ground-truth cameras": clip / "cameras"}
    for mode in args.modes:
        run_dir = out / "runs" / "main" / mode
        tracked = track_clip(clip, run_dir, TrackingConfig(mode=mode, lag_frames=args.lag), args.reuse_runs, progress)
        report.setdefault("tracking", {})[mode] = {k: tracked[k] for k in ("wall_s", "reused", "error", "frames_written")}
        sources[mode] = run_dir
    if not args.no_per_frame:
        run_dir = out / "runs" / "main" / "per-frame"
        if not (args.reuse_runs and RunFolder(run_dir).has_summary()):
            report.setdefault("tracking", {})["per-frame"] = per_frame_run(clip, run_dir, progress)
        sources["per-frame"] = run_dir
    for name, run_dir in sources.items():
        result = players_from_run(run_dir, boxes, out / "players" / name.replace(" ", "-"), options, progress=False)
        scored = score_players(result.lines, truth, true_cameras, fps, options.smooth_frames)
        scored["median_std_m"] = result.summary.get("median_std_m")
        positions = positions_from_lines(result.lines)
        scored["jitter_second_difference_m"] = _jitter_stats(
            all_jitter_m(positions.frame, positions.track_id, positions.xy_m))
        scored["camera_jitter_second_difference_m"] = _jitter_stats(camera_jitter_m(read_track(run_dir), positions))
        report["sources"][name] = scored
    report["detector_boxes"] = detector_box_bottoms(clip, boxes)
    return report


def detector_box_bottoms(clip: Path, boxes, every: int = 5, min_height_px: float = 30.0) -> dict:
    """The weight-free detector's player boxes against a clip's ground-truth boxes (every ``every``-th frame).

    Each true box at least ``min_height_px`` tall is matched to the detector's box of largest IoU (at least
    0.3); the bottom's error (true bottom minus the detector's, positive: the box ends above the feet) is given in
    shares of the true box's height.
    """
    import cv2

    from broadtrack_graph.detect.player_ids import box_iou
    from broadtrack_graph.detect.weightfree import WeightFreeDetector

    detector = WeightFreeDetector()
    errors, truths = [], 0
    for frame in boxes.frames[::every]:
        image = cv2.imread(str(clip / "img1" / f"{frame.frame_id}.jpg"))
        if image is None:
            continue
        found = detector.find_markings(image).unnamed.player_boxes_px
        true = frame.boxes_px[(frame.boxes_px[:, 3] - frame.boxes_px[:, 1]) >= min_height_px]
        truths += len(true)
        if not len(true) or not len(found):
            continue
        iou = box_iou(true, found)
        matched = iou.max(axis=1) >= 0.3
        bottoms = found[iou.argmax(axis=1), 3]
        errors.extend(((true[:, 3] - bottoms) / (true[:, 3] - true[:, 1]))[matched])
    shares = dict.fromkeys(("median", "abs_mean", "within_10_pct", "over_20_pct"))
    if errors:
        e = np.abs(np.array(errors))
        shares.update(median=np.median(errors), abs_mean=e.mean(), within_10_pct=np.mean(e < 0.1),
                      over_20_pct=np.mean(e > 0.2))
        shares = {k: round(float(v), 3) for k, v in shares.items()}
    return {"true_boxes": truths, "matched": len(errors), "bottom_error_share_of_height": shares}


# --------------------------------------------------------------------------- real clip


def _real(args, progress: bool) -> dict:
    from broadtrack_graph.actions.players import PlayersOptions, players_from_run
    from broadtrack_graph.actions.track import DETECTOR_BOXES, DetectorOptions, track_input
    from broadtrack_graph.io.players_file import boxes_from_positions, read_players_file
    from broadtrack_graph.io.run_folder import read_track
    from broadtrack_graph.metrics.players import all_jitter_m
    from broadtrack_graph.track.config import TrackingConfig

    out = Path(args.real_out or Path(args.out) / "real")
    report = {"clip": str(args.real), "out": str(out), "modes": {}}
    end = args.real_frames
    for mode in ("online", "fixed-lag"):
        run_dir = out / "runs" / mode
        if args.reuse_runs and RunFolder(run_dir).has_summary() and (mode != "online" or (run_dir / PLAYERS_FILE).is_file()):
            report["modes"][mode] = {"track_wall_s": None, "reused": True}
            continue
        started = time.perf_counter()
        track_input(args.real, out / "runs" / mode, TrackingConfig(mode=mode, lag_frames=args.lag),
                    DetectorOptions("weightfree"), end=end, progress=progress,
                    players=DETECTOR_BOXES if mode == "online" else None)
        report["modes"][mode] = {"track_wall_s": round(time.perf_counter() - started, 1)}
    # The same boxes (the online run's detector blobs, linked by IoU) through both runs' cameras.
    boxes = boxes_from_positions(read_players_file(out / "runs" / "online"))
    for mode in ("online", "fixed-lag"):
        result = players_from_run(out / "runs" / mode, boxes, out / "players" / mode,
                                  PlayersOptions(video=True), progress=progress)
        positions = read_players_file(out / "players" / mode)
        jitter = all_jitter_m(positions.frame, positions.track_id, positions.xy_m)
        report["modes"][mode].update({
            "boxes": result.boxes, "located": result.located, "no_camera": result.no_camera,
            "median_std_m": result.summary.get("median_std_m"),
            "jitter_second_difference_m": _jitter_stats(jitter),
            "camera_jitter_second_difference_m": _jitter_stats(camera_jitter_m(read_track(out / "runs" / mode),
                                                                               positions)),
            "analytics": result.summary["analytics"],
            "video": str(out / "players" / mode / "birdseye_players.mp4"),
        })
    return report


def run(args) -> dict:
    progress = not args.no_progress
    report = {"synthetic": _synthetic(args, progress)}
    real = args.real
    if real is not None and str(real).lower() != "none":
        if not Path(real).is_file():
            log.warning("real clip %s not found; real part skipped", real)
            report["real"] = {"skipped": f"{real} not found"}
        else:
            report["real"] = _real(args, progress)
    return report
