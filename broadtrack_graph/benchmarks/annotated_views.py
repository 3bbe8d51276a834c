"""``broadtrack-graph bench placements --annotations DIR``: the court model on real broadcast views' own markings.

SoccerNet's line annotations (``NNNNN.json``, read by :mod:`broadtrack_graph.io.annotations`) trace the markings of
real broadcast frames: main cameras zoomed on a penalty area, wide views, cameras behind the goals, with their real
positions, lenses and zooms. Each frame's ground markings are drawn as the detector's marking map would show them
(a line one pixel wide along every annotated polyline, its points every pixel along it:
:func:`annotation_marking_map`), and the single-frame court model
(:func:`broadtrack_graph.reinit.court.reinit_from_court`) is asked for its camera on one core. No image is read:
this measures the court model's reach over real cameras' geometry, apart from detection (players, graphics and
blur are not drawn; no field map is given to the confidence).

A frame **counts** when its annotated markings determine a camera (:func:`annotated_determinability`: two distinct
straight ground markings of each of the pitch's directions annotated along ``MIN_LINE_PX`` pixels or more each, or a
circle or arc annotated along that many and one such line; the geometric rule of
:mod:`broadtrack_graph.geometry.determinable`, read on the annotation instead of a true camera). The camera is
**written** when at least as confident as the tracker takes the court model's camera
(:func:`~broadtrack_graph.track.reinit_policy.court_accept_at`), and judged by SoccerNet's own metric
(:func:`~broadtrack_graph.metrics.soccernet.evaluate_frame`: each annotated point's distance to its class's projected
template, the better of the labelling and its mirror, which is the twin the markings cannot tell apart): **found**,
written with the median distance at most ``--success-px``; **wrong**, written and over
:data:`~broadtrack_graph.benchmarks.random_placements.WRONG_PX`; **near**, written between the two; **none**, not
written. The annotators' own clicks lie a pixel or two off the markings.
"""

from __future__ import annotations

import sys
import time

import numpy as np

from broadtrack_graph.benchmarks.placement_figures import OUTCOMES
from broadtrack_graph.benchmarks.random_placements import WRONG_PX, outcome


def annotation_marking_map(lines_norm: dict, width_px: int, height_px: int, pitch) -> tuple[np.ndarray, np.ndarray]:
    """The marking map and centre-line points of a frame's annotated ground markings.

    Args:
        lines_norm: class name -> (N, 2) normalised annotation coordinates (:mod:`broadtrack_graph.io.annotations`).
        width_px, height_px: the frame size drawn at.
        pitch: the :class:`~broadtrack_graph.geometry.pitch.PitchTemplate` (which classes lie on the grass).

    Returns:
        (H, W) bool map, each polyline drawn one pixel wide; (M, 2) points every pixel along the polylines, frame
        pixels (SoccerNet's rule: ``x * (W - 1), y * (H - 1)``).
    """
    import cv2

    marking_map = np.zeros((height_px, width_px), np.uint8)
    points = []
    scale = np.array([width_px - 1, height_px - 1], float)
    for name, normalised in lines_norm.items():
        if not pitch.is_on_ground(name) or len(normalised) < 2:
            continue
        polyline = np.asarray(normalised, float) * scale
        cv2.polylines(marking_map, [np.round(polyline * 8).astype(np.int32)], False, 255, 1, cv2.LINE_8, 3)
        starts, steps = polyline[:-1], np.diff(polyline, axis=0)
        counts = np.maximum(np.linalg.norm(steps, axis=1).astype(int), 1)
        segment = np.repeat(np.arange(len(steps)), counts)
        share = np.concatenate([np.arange(n) / n for n in counts])
        points.append(starts[segment] + share[:, None] * steps[segment])
    return marking_map > 0, (np.vstack(points) if points else np.zeros((0, 2)))


def annotated_determinability(lines_norm: dict, width_px: int, height_px: int, pitch) -> tuple[bool, dict]:
    """Whether a frame's annotated ground markings determine a camera (module docstring), and what they hold:
    {"x_lines", "y_lines": distinct straight markings of each direction annotated along ``MIN_LINE_PX`` or more,
    "curves": circle classes annotated along that many} (:func:`~broadtrack_graph.geometry.determinable.
    determinability_of_lengths`, the annotated polylines' lengths for the projected ones)."""
    from broadtrack_graph.geometry.determinable import MIN_LINE_PX, determinability_of_lengths
    from broadtrack_graph.geometry.pitch import CIRCLE_CLASSES

    scale = np.array([width_px - 1, height_px - 1], float)
    length_px = {name: float(np.linalg.norm(np.diff(np.asarray(points, float) * scale, axis=0), axis=1).sum())
                 for name, points in lines_norm.items() if pitch.is_on_ground(name) and len(points) >= 2}
    curves = tuple(sorted(n for n, length in length_px.items() if n in CIRCLE_CLASSES and length >= MIN_LINE_PX))
    seen = determinability_of_lengths(length_px, curves, pitch)
    return seen.determinable, {"x_lines": seen.x_lines, "y_lines": seen.y_lines, "curves": list(seen.curves)}


def run(args) -> dict:
    """The report of ``bench placements --annotations DIR`` (module docstring); a short table goes to stderr."""
    import cv2
    from tqdm import tqdm

    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.geometry.template import TemplateSampling, fitting_curves
    from broadtrack_graph.io.annotations import read_annotations
    from broadtrack_graph.metrics.soccernet import evaluate_frame
    from broadtrack_graph.reinit.court import reinit_from_court
    from broadtrack_graph.track.config import TrackingConfig
    from broadtrack_graph.track.frame_tries import court_accept_at

    annotations = read_annotations(args.annotations)
    if not annotations.frames:
        from broadtrack_graph.errors import InputError

        raise InputError(args.annotations, annotations.no_frames_reason())
    W, H = args.width, args.height
    pitch = PitchTemplate()
    curves, sampling = fitting_curves(pitch), TemplateSampling(pitch)
    config = TrackingConfig()
    frame_ids = sorted(annotations.frames)[args.first:]
    if args.limit is not None:
        frame_ids = frame_ids[:args.limit]
    threads = cv2.getNumThreads()
    cv2.setNumThreads(1)
    rows = []
    try:
        for frame_id in tqdm(frame_ids, desc="annotated views", unit="frame", disable=args.no_progress):
            lines = {name: points for name, points in annotations.frames[frame_id].items() if pitch.is_on_ground(name)}
            determinable, held = annotated_determinability(lines, W, H, pitch)
            marking_map, points = annotation_marking_map(lines, W, H, pitch)
            started = time.process_time()
            result = reinit_from_court(marking_map, points, (W, H), pitch=pitch, curves=curves)
            seconds = time.process_time() - started
            confidence = error = None
            if result.camera is not None:
                confidence = float(result.score.jaccard)
                distances = evaluate_frame(lines, result.camera, W, H, (5.0,), sampling).all_distances(5.0)
                error = float(np.median(distances)) if len(distances) else None
            written_at = court_accept_at(config, result) if result.camera is not None else 1.0
            rows.append({"frame": frame_id, "determinable": determinable, **held,
                         "outcome": outcome(confidence, error, written_at, args.success_px),
                         "error_px": None if error is None else round(error, 2),
                         "confidence": None if confidence is None else round(confidence, 3),
                         "written_at": round(written_at, 3), "seconds": round(seconds, 3), "reason": result.reason})
    finally:
        cv2.setNumThreads(threads)
    report = {"source": str(args.annotations), "frame_size": [W, H], "success_px": args.success_px,
              "wrong_px": WRONG_PX, "unreadable": len(annotations.errors), **summarise(rows), "frames": rows}
    print(summary_table(report), file=sys.stderr)
    return report


def summarise(rows: list[dict]) -> dict:
    """Counts and shares (% of the determinable frames) of each outcome, the seconds a determinable frame (median,
    95th percentile), and the cameras written on the frames apart."""
    counted = [row for row in rows if row["determinable"]]
    counts = {name: sum(row["outcome"] == name for row in counted) for name in OUTCOMES}
    seconds = [row["seconds"] for row in counted]
    return {"frames_read": len(rows), "determinable": len(counted),
            "counts": counts,
            "shares_pct": {name: round(100.0 * n / max(len(counted), 1), 1) for name, n in counts.items()},
            "seconds": {"median": round(float(np.median(seconds)), 3) if seconds else None,
                        "p95": round(float(np.percentile(seconds, 95)), 3) if seconds else None},
            "apart_written": {name: sum(row["outcome"] == name for row in rows if not row["determinable"])
                              for name in ("found", "near", "wrong")}}


def summary_table(report: dict) -> str:
    """Two lines for a human (stderr)."""
    shares = report["shares_pct"]
    return (f"annotated views: {report['determinable']} of {report['frames_read']} determinable; found "
            f"{shares['found']} %, near {shares['near']} %, wrong {shares['wrong']} %, none {shares['none']} %\n"
            f"seconds a frame: median {report['seconds']['median']}, p95 {report['seconds']['p95']}")
