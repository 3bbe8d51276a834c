"""Agreement of a camera with per-class (labelled) detections, and the outcome of a re-initialisation. No I/O."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.determinable import Determinability
from broadtrack_graph.geometry.template import TemplateSampling, distances_to_polyline, project_template_polylines


@dataclass
class LabelledScore:
    """Agreement of a camera with per-class detections at threshold tau (the JaC of the SoccerNet metric).

    jaccard: TP / (TP + FP + FN) over classes; tp/fp/fn: class counts; inlier_share: share of points within tau.
    """

    jaccard: float
    tp: int
    fp: int
    fn: int
    inlier_share: float
    mean_distance_px: float


def score_labelled(camera: Camera, lines_px: dict[str, np.ndarray], tau_px: float = 5.0,
                   sampling: TemplateSampling | None = None) -> LabelledScore:
    """Per-class agreement: a class detected and projected is TP when all its points are within tau_px.

    Classes projected but not detected count as FP, detected but not projected as FN.
    """
    polylines = project_template_polylines(camera, camera.width_px, camera.height_px, sampling)
    tp = fp = fn = 0
    inliers = total = 0
    distance_sum = 0.0
    for name, points in lines_px.items():
        if not len(points):
            continue
        poly = polylines.get(name)
        if poly is None or len(poly) == 0:
            fn += 1
            total += len(points)
            continue
        if len(poly) == 1:
            distances = np.linalg.norm(points - poly[0], axis=1)
        else:
            distances = distances_to_polyline(np.asarray(points, float), poly)
        inliers += int(np.sum(distances < tau_px))
        total += len(points)
        distance_sum += float(np.sum(np.minimum(distances, 100.0)))
        if distances.max() < tau_px:
            tp += 1
        else:
            fp += 1
    fp += sum(1 for name in polylines if name not in lines_px)
    jac = tp / max(tp + fp + fn, 1)
    return LabelledScore(jac, tp, fp, fn, inliers / max(total, 1), distance_sum / max(total, 1))


@dataclass
class ReinitResult:
    """Outcome of a re-initialisation: camera (None when nothing fits), score, which hypothesis won, reason."""

    camera: Camera | None
    score: LabelledScore | None
    hypothesis: str
    reason: str = ""
    tried: int = 0
    twin: Camera | None = None  # the camera half a turn round the centre spot, which explains the markings as well
    explained: Determinability | None = None  # the markings the camera explains on the map (the court model's)
