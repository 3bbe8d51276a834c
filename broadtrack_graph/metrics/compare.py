"""Compare camera tracks (filter vs smoother, or any runs): metrics, jitter, focal point spread, plots.

Figures per run (all computed over the frames that have a camera):

* SoccerNet metric when annotations are given (JaC@5, JaC@10 = accuracy at tau,
  completeness, final score, MRE / MedRE at tau 5), from :mod:`broadtrack_graph.metrics.soccernet`.
* Jitter of pan, tilt (deg) and focal length (px): the RMS of the first
  difference ``x[t] - x[t-1]`` (per frame; includes the real motion) and the RMS of
  the second difference ``x[t+1] - 2 x[t] + x[t-1]`` (per frame^2; real broadcast
  motion is smooth, so this is mostly noise). Only runs of consecutive frame
  indices with a camera count; pan differences are wrapped to (-180, 180].
* Spread of the focal point C: standard deviation per axis (population, ddof 0),
  extent (max - min) per axis, and RMS distance to the mean position, metres.
* Error against ground-truth cameras when given: RMS of pan / tilt / roll errors
  (deg), mean absolute relative focal error (%), RMS position error (m).
* Players, when a run folder has a ``players.jsonl``: boxes located, total distance
  covered, median and largest top speed, median jitter over tracks
  (:mod:`broadtrack_graph.metrics.players`: light smoothing over time before distances
  and speeds; jitter from the raw positions).

Numbers only: :func:`broadtrack_graph.actions.compare.compare_runs` reads the runs and writes
the report (:mod:`broadtrack_graph.products.compare_report`).
"""

from __future__ import annotations

import logging

import numpy as np

from broadtrack_graph.types.track_record import RunRecords

logger = logging.getLogger(__name__)

COMPARE_TAUS = (5.0, 10.0)


# --------------------------------------------------------------------------- numbers


def _consecutive_differences(values: np.ndarray, frame_indices: np.ndarray, wrap_deg: bool) -> tuple[np.ndarray, np.ndarray]:
    values = np.asarray(values, dtype=float)
    frames = np.asarray(frame_indices, dtype=float)
    order = np.argsort(frames, kind="stable")
    values, frames = values[order], frames[order]
    d1 = np.diff(values)
    if wrap_deg:
        d1 = (d1 + 180.0) % 360.0 - 180.0
    step_ok = np.diff(frames) == 1
    first_ok = step_ok & np.isfinite(d1)
    d2 = d1[1:] - d1[:-1]
    second_ok = first_ok[1:] & first_ok[:-1]
    return d1[first_ok], d2[second_ok]


def jitter(values: np.ndarray, frame_indices: np.ndarray, wrap_deg: bool = False) -> dict:
    """RMS of the first and second differences of a per-frame series.

    Args:
        values: (N,) the series (NaN where a frame has no camera).
        frame_indices: (N,) frame index of each value; only steps of exactly 1 count.
        wrap_deg: wrap first differences to (-180, 180] (for pan in degrees).

    Returns:
        {"rms_d1": RMS(x[t] - x[t-1]), "rms_d2": RMS(x[t+1] - 2 x[t] + x[t-1]),
         "pairs": number of first differences, "triples": number of second differences};
        None values when there are no pairs / triples.
    """
    d1, d2 = _consecutive_differences(values, frame_indices, wrap_deg)
    return {
        "rms_d1": float(np.sqrt(np.mean(d1**2))) if len(d1) else None,
        "rms_d2": float(np.sqrt(np.mean(d2**2))) if len(d2) else None,
        "pairs": int(len(d1)),
        "triples": int(len(d2)),
    }


def focal_point_spread(positions_m: np.ndarray) -> dict:
    """Spread of focal point positions.

    Args:
        positions_m: (N, 3) C per frame, metres (NaN rows are ignored).

    Returns:
        {"frames", "mean_m" (3,), "std_m" (3,) population std per axis, "extent_m" (3,)
        max - min per axis, "rms_to_mean_m"}; None values without frames.
    """
    positions = np.asarray(positions_m, dtype=float).reshape(-1, 3)
    positions = positions[np.all(np.isfinite(positions), axis=1)]
    if not len(positions):
        return {"frames": 0, "mean_m": None, "std_m": None, "extent_m": None, "rms_to_mean_m": None}
    mean = positions.mean(axis=0)
    return {
        "frames": int(len(positions)),
        "mean_m": mean.tolist(),
        "std_m": positions.std(axis=0).tolist(),
        "extent_m": (positions.max(axis=0) - positions.min(axis=0)).tolist(),
        "rms_to_mean_m": float(np.sqrt(np.mean(np.sum((positions - mean) ** 2, axis=1)))),
    }


def track_statistics(track: RunRecords) -> dict:
    """Jitter, focal point spread and counts of one track (see the module docstring)."""
    states = track.states()
    frames = track.frame_indices
    confidences = track.confidences()
    with_camera = int(np.isfinite(states[:, 0]).sum())
    return {
        "path": str(track.path),
        "resolution": [track.width_px, track.height_px],
        "frames": len(track),
        "frames_with_camera": with_camera,
        "share_with_camera": with_camera / len(track) if len(track) else None,
        "reinitialisations": int(sum(r.reinitialised for r in track.records)),
        "mean_confidence": float(np.nanmean(confidences)) if np.isfinite(confidences).any() else None,
        "jitter": {
            "pan_deg": jitter(states[:, 2], frames, wrap_deg=True),
            "tilt_deg": jitter(states[:, 3], frames),
            "focal_px": jitter(states[:, 0], frames),
        },
        "focal_point": focal_point_spread(states[:, 5:8]),
    }


def ground_truth_errors(track: RunRecords, truth: RunRecords) -> dict:
    """Camera parameter errors against ground truth, over frame ids present in both with cameras.

    Returns:
        {"frames", "pan_rms_deg", "tilt_rms_deg", "roll_rms_deg", "focal_mean_abs_rel_pct",
        "position_rms_m"} (None values when no frame matches).
    """
    truth_by_id = truth.cameras
    pairs = [
        (record.camera, truth_by_id[record.frame_id])
        for record in track.records
        if record.camera is not None and truth_by_id.get(record.frame_id) is not None
    ]
    if not pairs:
        return {"frames": 0, "pan_rms_deg": None, "tilt_rms_deg": None, "roll_rms_deg": None,
                "focal_mean_abs_rel_pct": None, "position_rms_m": None}
    est = np.array([[c.pan_deg, c.tilt_deg, c.roll_deg, c.focal_px / c.width_px, *c.position_m] for c, _ in pairs])
    ref = np.array([[c.pan_deg, c.tilt_deg, c.roll_deg, c.focal_px / c.width_px, *c.position_m] for _, c in pairs])
    error = est - ref
    error[:, 0] = (error[:, 0] + 180.0) % 360.0 - 180.0
    rms = np.sqrt(np.mean(error**2, axis=0))
    return {
        "frames": len(pairs),
        "pan_rms_deg": float(rms[0]),
        "tilt_rms_deg": float(rms[1]),
        "roll_rms_deg": float(rms[2]),
        "focal_mean_abs_rel_pct": float(100 * np.mean(np.abs(error[:, 3]) / ref[:, 3])),
        "position_rms_m": float(np.sqrt(np.mean(np.sum(error[:, 4:7] ** 2, axis=1)))),
    }


def metric_summary(annotations, track: RunRecords, width_px: int, height_px: int, taus=COMPARE_TAUS) -> dict:
    """The SoccerNet metric of one track on the annotated frames (JaC per tau, completeness, MRE).

    Returns:
        {"frames_annotated", "frames_matched" (annotated ids present in the track),
        "frames_with_camera", "completeness", "jac" {tau: accuracy}, "final_score" {tau: ...},
        "mre_px", "medre_px" (at the first tau), "resolution"}.
    """
    from broadtrack_graph.metrics.soccernet import evaluate_cameras

    cameras = track.cameras
    matched = sum(1 for frame_id in annotations.frames if frame_id in cameras)
    if annotations.frames and not matched:
        logger.warning("%s: no annotated frame id is in the track (ids like %s vs %s)", track.path,
                       next(iter(annotations.frames)), next(iter(cameras), None))
    report = evaluate_cameras(annotations, cameras, width_px, height_px, taus)
    first = f"{taus[0]:g}"
    return {
        "frames_annotated": report["frames"],
        "frames_matched": matched,
        "frames_with_camera": report["frames_with_camera"],
        "completeness": report["completeness"],
        "jac": {key: row["accuracy"] for key, row in report["taus"].items()},
        "final_score": {key: row["final_score"] for key, row in report["taus"].items()},
        "mre_px": report["taus"][first]["mre_px"],
        "medre_px": report["taus"][first]["medre_px"],
        "resolution": [int(width_px), int(height_px)],
    }


# --------------------------------------------------------------------------- several tracks


def tripod_from_summary(track: RunRecords):
    """(3,) tripod point T_w of a run's summary.json (``"tripod": {"T_w": [x, y, z]}``), or None."""
    tripod = track.summary.get("tripod") if isinstance(track.summary, dict) else None
    if isinstance(tripod, dict) and isinstance(tripod.get("T_w"), list) and len(tripod["T_w"]) == 3:
        return np.asarray(tripod["T_w"], dtype=float)
    return None


def player_statistics(positions, fps: float = 25.0, smooth_frames: int = 5) -> dict:
    """Player figures of a run: boxes, located, and the track analytics summary (see the module docstring).

    Args:
        positions: a :class:`~broadtrack_graph.io.players_file.PlayerPositions`.
        fps: frames per second of the clip.
        smooth_frames: centred moving-average window for distances and speeds.
    """
    from broadtrack_graph.metrics.players import AnalyticsConfig, analytics_summary, track_analytics

    per_track = track_analytics(positions.frame, positions.track_id, positions.xy_m,
                                AnalyticsConfig(fps=fps, smooth_frames=smooth_frames))
    return {"boxes": int(len(positions)), "located": int(positions.has_position.sum()),
            **analytics_summary(per_track),
            "per_track_distance_m": {str(k): round(v["distance_m"], 3) for k, v in per_track.items()}}


def compare_tracks(tracks: dict[str, RunRecords], truth: RunRecords | None = None, annotations=None,
                   eval_size_px: tuple[int, int] | None = None, taus=COMPARE_TAUS,
                   players: dict | None = None, fps: dict | None = None) -> dict:
    """The figures of several tracks: {"runs": name -> figures, "taus": [...]}.

    Args:
        tracks: name -> track.
        truth: ground-truth cameras for parameter errors, or None.
        annotations: an AnnotationSet for the SoccerNet metric, or None.
        eval_size_px: (W, H) evaluation resolution (default: the annotations' image size
            when the file states it, else each track's own resolution).
        taus: metric thresholds, pixels.
        players: name -> PlayerPositions of the runs that have players (others get none).
        fps: name -> frames per second (default 25).
    """
    report: dict = {"runs": {}, "taus": [float(t) for t in taus]}
    for name, track in tracks.items():
        stats = track_statistics(track)
        if annotations is not None:
            size = eval_size_px or _annotation_size(annotations) or (track.width_px, track.height_px)
            stats["metrics"] = metric_summary(annotations, track, size[0], size[1], taus)
        if truth is not None:
            stats["ground_truth_error"] = ground_truth_errors(track, truth)
        if players and players.get(name) is not None:
            stats["players"] = player_statistics(players[name], (fps or {}).get(name, 25.0))
        report["runs"][name] = stats
    return report


DEFINITIONS = {
    "jitter rms_d1": "RMS over consecutive frames of x[t] - x[t-1] (deg or px per frame)",
    "jitter rms_d2": "RMS over consecutive frames of x[t+1] - 2 x[t] + x[t-1] (deg or px per frame^2)",
    "focal_point std_m": "population standard deviation of C per axis (metres)",
    "focal_point extent_m": "max - min of C per axis (metres)",
    "JaC@tau": "SoccerNet accuracy at tau px: mean per-frame Jaccard over annotated frames with a camera",
    "players distance": "distance covered summed over tracks, positions smoothed by a centred 5-frame moving average",
    "players jitter": "RMS of the second difference of raw positions over consecutive frames, median over tracks (m)",
    "MRE/MedRE": "mean / median distance of annotated points to their projected class, at the first tau",
}
"""What the comparison's figures mean (stored in compare.json and listed under the table)."""


def _annotation_size(annotations) -> tuple[int, int] | None:
    sizes = set(annotations.image_sizes.values())
    return next(iter(sizes)) if len(sizes) == 1 else None
