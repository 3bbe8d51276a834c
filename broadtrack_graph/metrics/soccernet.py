"""The SoccerNet camera calibration metric (JaC@tau, completeness, final score) and MRE.

It reproduces the official SoccerNet evaluation rule for rule:

* every pitch class is projected into the image as the official evaluation does
  (its template sampling, float32-rounded projection and border points:
  :func:`broadtrack_graph.geometry.template.project_template_polylines`);
* per class: projected but not annotated -> FP; annotated but not projected -> FN;
  both -> TP if every annotated point is strictly closer than tau pixels to the
  projected polyline (point-to-segment distance), else FP;
* JaC = TP / (TP + FP + FN); the frame is also scored with the labels mirrored
  through the pitch centre, and the mirrored score is kept unless the original
  one is strictly higher (decided per tau, as the official tool runs per tau);
* accuracy = mean JaC over annotated frames with a camera; completeness = share of
  annotated frames with a camera; final score = accuracy x completeness;
  precision and recall are per-frame means over the frames where they are defined.

Differences from the official script, all on inputs it cannot handle: a camera
file at another resolution is rescaled to the evaluation resolution (the official
script uses the file's intrinsics as they are, which agrees when the file is at the
evaluation resolution); a broken camera file counts as a missing camera and is
reported; a broken annotation file is reported and left out.

Also reported: the mean and median distance (pixels) of annotated points to their
projected class (MRE, MedRE), over classes both annotated and projected, with the
labelling chosen at each tau.

This module does no I/O; :func:`evaluate_folders` in the command module reads files.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import LINE_CLASSES, MIRRORED_CLASS, PitchTemplate
from broadtrack_graph.geometry.template import TemplateSampling, distances_to_polyline, project_template_polylines

DEFAULT_TAUS = (5.0, 10.0, 20.0)
"""The metric's pixel thresholds tau (JaC@5, @10, @20)."""


# --------------------------------------------------------------------------- one frame


@dataclass
class LabellingScore:
    """Scores of one frame under one labelling (original or mirrored)."""

    tp: dict[float, int]
    fp: dict[float, int]
    fn: int
    distances: dict[str, np.ndarray]  # class -> (M,) distances of its annotated points
    false_positive_classes: list[str]
    false_negative_classes: list[str]

    def jac(self, tau: float) -> float:
        total = self.tp[tau] + self.fp[tau] + self.fn
        return self.tp[tau] / total if total > 0 else 0.0


@dataclass
class FrameScore:
    """The metric of one frame at each tau (the labelling chosen per tau)."""

    jac: dict[float, float]
    tp: dict[float, int]
    fp: dict[float, int]
    fn: dict[float, int]
    mirrored: dict[float, bool]
    distances: dict[float, dict[str, np.ndarray]]
    class_outcome: dict[float, dict[str, str]] = field(default_factory=dict)  # class -> "tp" | "fp" | "fn"

    def all_distances(self, tau: float) -> np.ndarray:
        values = list(self.distances[tau].values())
        return np.concatenate(values) if values else np.zeros(0)


def _score_labelling(lines_px: dict[str, np.ndarray], polylines: dict[str, np.ndarray], taus) -> LabellingScore:
    annotated = set(lines_px)
    projected = set(polylines)
    fp_classes = sorted(projected - annotated)
    fn_classes = sorted(annotated - projected)
    distances = {name: distances_to_polyline(lines_px[name], polylines[name]) for name in sorted(annotated & projected)}
    tp = {tau: 0 for tau in taus}
    fp = {tau: len(fp_classes) for tau in taus}
    for values in distances.values():
        worst = float(values.max())
        for tau in taus:
            if worst < tau:
                tp[tau] += 1
            else:
                fp[tau] += 1
    return LabellingScore(tp, fp, len(fn_classes), distances, fp_classes, fn_classes)


def evaluate_frame(
    lines_norm: dict[str, np.ndarray],
    camera: Camera,
    width_px: int,
    height_px: int,
    taus=DEFAULT_TAUS,
    sampling: TemplateSampling | None = None,
) -> FrameScore:
    """Score one camera against one frame's line annotation.

    Args:
        lines_norm: class name -> (N, 2) normalised annotation coordinates (names stripped).
        camera: the camera to score (rescaled to the evaluation resolution if needed).
        width_px, height_px: evaluation resolution.
        taus: pixel thresholds.
        sampling: reusable template sampling.

    Returns:
        The frame's FrameScore.
    """
    taus = tuple(float(t) for t in taus)
    scale = np.array([width_px - 1, height_px - 1], dtype=float)
    lines_px = {name: np.asarray(points, dtype=float) * scale for name, points in lines_norm.items() if len(points)}
    polylines = project_template_polylines(camera, width_px, height_px, sampling)
    original = _score_labelling(lines_px, polylines, taus)
    mirrored_lines = {MIRRORED_CLASS[name]: points for name, points in lines_px.items()}
    mirrored = _score_labelling(mirrored_lines, polylines, taus)
    result = FrameScore({}, {}, {}, {}, {}, {})
    for tau in taus:
        use_original = original.jac(tau) > mirrored.jac(tau)
        chosen = original if use_original else mirrored
        result.jac[tau] = chosen.jac(tau)
        result.tp[tau], result.fp[tau], result.fn[tau] = chosen.tp[tau], chosen.fp[tau], chosen.fn
        result.mirrored[tau] = not use_original
        result.distances[tau] = chosen.distances
        outcome = {name: "fp" for name in chosen.false_positive_classes}
        outcome.update({name: "fn" for name in chosen.false_negative_classes})
        for name, values in chosen.distances.items():
            outcome[name] = "tp" if float(values.max()) < tau else "fp"
        result.class_outcome[tau] = outcome
    return result


# --------------------------------------------------------------------------- a set of frames


def _tau_key(tau: float) -> str:
    return f"{tau:g}"


def evaluate_cameras(
    annotations,
    cameras: dict[str, Camera | None],
    width_px: int,
    height_px: int,
    taus=DEFAULT_TAUS,
    pitch: PitchTemplate | None = None,
    camera_errors: dict[str, str] | None = None,
    progress: bool = False,
) -> dict:
    """The SoccerNet camera metric over a set of annotated frames.

    Args:
        annotations: an :class:`~broadtrack_graph.io.annotations.AnnotationSet` (frames:
            frame id -> class -> (N, 2) normalised points; errors: frames left out).
        cameras: frame id -> Camera, or None for a frame with no usable camera.
        width_px, height_px: evaluation resolution.
        taus: pixel thresholds, several at once.
        pitch: the template (default 105 x 68).
        camera_errors: frame id -> message for camera files that could not be read.
        progress: show a tqdm bar.

    Returns:
        The JSON-ready report: frames, frames_with_camera, resolution, tau_values,
        final_score / completeness / accuracy / precision / recall / mre_px / medre_px
        at the first tau, ``taus`` (tau -> the same figures), per_class (tau -> class ->
        tp/fp/fn/jac), per_frame (frame id -> jac per tau, mirrored, mre_px), errors.
    """
    taus = tuple(float(t) for t in taus)
    if not taus:
        raise ValueError("at least one tau is needed")
    sampling = TemplateSampling(pitch)
    frame_ids = sorted(annotations.frames)
    scores: dict[str, FrameScore] = {}
    missing: list[str] = []
    iterator = frame_ids
    if progress:
        from tqdm import tqdm

        iterator = tqdm(frame_ids, desc="evaluate", unit="frame")
    for frame_id in iterator:
        camera = cameras.get(frame_id)
        if camera is None:
            missing.append(frame_id)
            continue
        scores[frame_id] = evaluate_frame(annotations.frames[frame_id], camera, width_px, height_px, taus, sampling)

    total = len(frame_ids)
    completeness = (total - len(missing)) / total if total else 0.0
    by_tau = {}
    per_class: dict[str, dict] = {}
    for tau in taus:
        jacs = [s.jac[tau] for s in scores.values()]
        precisions = [s.tp[tau] / (s.tp[tau] + s.fp[tau]) for s in scores.values() if s.tp[tau] + s.fp[tau] > 0]
        recalls = [s.tp[tau] / (s.tp[tau] + s.fn[tau]) for s in scores.values() if s.tp[tau] + s.fn[tau] > 0]
        distances = [s.all_distances(tau) for s in scores.values()]
        distances = np.concatenate(distances) if distances else np.zeros(0)
        accuracy = float(np.mean(jacs)) if jacs else 0.0
        by_tau[_tau_key(tau)] = {
            "tau_px": tau,
            "final_score": accuracy * completeness,
            "completeness": completeness,
            "accuracy": accuracy,
            "precision": float(np.mean(precisions)) if precisions else 0.0,
            "recall": float(np.mean(recalls)) if recalls else 0.0,
            "mre_px": float(np.mean(distances)) if len(distances) else None,
            "medre_px": float(np.median(distances)) if len(distances) else None,
            "mirrored_frames": int(sum(s.mirrored[tau] for s in scores.values())),
        }
        classes = {}
        for name in LINE_CLASSES + ("Line unknown", "Goal unknown"):
            counts = {"tp": 0, "fp": 0, "fn": 0}
            for s in scores.values():
                outcome = s.class_outcome[tau].get(name)
                if outcome:
                    counts[outcome] += 1
            seen = counts["tp"] + counts["fp"] + counts["fn"]
            if seen:
                classes[name] = {**counts, "jac": counts["tp"] / seen}
        per_class[_tau_key(tau)] = classes

    first = by_tau[_tau_key(taus[0])]
    errors = dict(getattr(annotations, "errors", {}) or {})
    for frame_id, message in (camera_errors or {}).items():
        if frame_id in annotations.frames:
            errors[frame_id] = message
    return {
        "frames": total,
        "frames_with_camera": total - len(missing),
        "resolution": [int(width_px), int(height_px)],
        "tau_values": list(taus),
        "final_score": first["final_score"],
        "completeness": completeness,
        "accuracy": first["accuracy"],
        "precision": first["precision"],
        "recall": first["recall"],
        "mre_px": first["mre_px"],
        "medre_px": first["medre_px"],
        "taus": by_tau,
        "per_class": per_class,
        "missing_cameras": missing,
        "errors": errors,
        "per_frame": {
            frame_id: {
                "jac": {_tau_key(t): s.jac[t] for t in taus},
                "mirrored": {_tau_key(t): s.mirrored[t] for t in taus},
                "mre_px": float(np.mean(s.all_distances(taus[0]))) if len(s.all_distances(taus[0])) else None,
            }
            for frame_id, s in scores.items()
        },
    }
