"""Single-frame calibration from per-class marking points (SoccerNet annotations as detections).

Each frame's labelled line points are treated as the output of a perfect line
detector: :func:`broadtrack_graph.reinit.lines.reinit_from_lines` forms several
hypotheses (homography of the straight ground lines, global pan/tilt/f search at the
default tripod positions and their mirrors), refines each and keeps the best by the
per-class score. No image is needed. No I/O here: :func:`calibrate_annotation_set`
hands every camera to a callback (the command writes the files as they come).
"""

from __future__ import annotations

import logging
import os
from collections.abc import Callable
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.template import TemplateSampling
from broadtrack_graph.geometry.template import TemplateCurves
from broadtrack_graph.reinit.lines import ReinitConfig, reinit_from_lines
from broadtrack_graph.reinit.scoring import ReinitResult
from broadtrack_graph.io.annotations import AnnotationSet, annotation_to_pixels
from broadtrack_graph.geometry.pitch import PitchTemplate

log = logging.getLogger(__name__)


@dataclass
class FrameCalibration:
    """Result for one frame: camera (None when nothing could be fitted, see reason) and diagnostics."""

    frame_id: str
    camera: Camera | None
    hypothesis: str
    jaccard: float  # per-class agreement with the frame's own points at tau (not mirrored)
    inlier_share: float  # share of points within tau
    reason: str = ""


class _Calibrator:
    """Template samplings built once per process."""

    def __init__(self, width_px: int, height_px: int, config: ReinitConfig, pitch: PitchTemplate | None = None):
        self.pitch = pitch or PitchTemplate()
        self.curves = TemplateCurves(self.pitch)
        self.sampling = TemplateSampling(self.pitch)
        self.width_px, self.height_px = width_px, height_px
        self.config = config

    def __call__(self, frame_id: str, lines_norm: dict[str, np.ndarray]) -> FrameCalibration:
        lines_px = annotation_to_pixels(lines_norm, self.width_px, self.height_px)
        result: ReinitResult = reinit_from_lines(
            lines_px, self.width_px, self.height_px, self.pitch, config=self.config,
            curves=self.curves, sampling=self.sampling,
        )
        if result.camera is None:
            return FrameCalibration(frame_id, None, "", 0.0, 0.0, result.reason)
        return FrameCalibration(frame_id, result.camera, result.hypothesis, result.score.jaccard,
                                result.score.inlier_share)


def calibrate_lines(lines_px: dict[str, np.ndarray], width_px: int, height_px: int,
                    config: ReinitConfig = ReinitConfig()) -> ReinitResult:
    """Calibrate one frame from class name -> (M, 2) pixel points (see module docstring)."""
    return reinit_from_lines(lines_px, width_px, height_px, config=config)


_WORKER: _Calibrator | None = None


def _init_worker(width_px, height_px, config):
    global _WORKER
    _WORKER = _Calibrator(width_px, height_px, config)


def _work(item):
    return _WORKER(*item)


def calibrate_annotation_set(
    annotations: AnnotationSet,
    width_px: int,
    height_px: int,
    on_result: Callable[[FrameCalibration], None] | None = None,
    config: ReinitConfig = ReinitConfig(),
    jobs: int = 1,
    progress: bool = True,
) -> dict:
    """Calibrate every annotated frame; ``on_result`` receives each frame as soon as it is done.

    Args:
        annotations: frames to calibrate (normalised coordinates).
        width_px, height_px: resolution of the cameras produced.
        on_result: callback (e.g. writing camera_<id>.json), called in frame order.
        jobs: worker processes (1 = in this process).
        progress: show a tqdm bar.

    Returns:
        Summary: frames, cameras, missing (frame id -> reason), hypotheses (name -> count),
        mean_self_jaccard, mean_inlier_share.
    """
    from tqdm import tqdm

    items = [(frame_id, annotations.frames[frame_id]) for frame_id in sorted(annotations.frames)]
    jobs = max(1, min(int(jobs), os.cpu_count() or 1))
    summary = {"frames": len(items), "cameras": 0, "missing": {}, "hypotheses": {}}
    jaccards, inliers = [], []
    bar = tqdm(total=len(items), desc="calibrate", unit="frame", disable=not progress)

    def handle(result: FrameCalibration) -> None:
        bar.update(1)
        if result.camera is None:
            summary["missing"][result.frame_id] = result.reason
        else:
            summary["cameras"] += 1
            kind = result.hypothesis.split(" at ")[0]
            summary["hypotheses"][kind] = summary["hypotheses"].get(kind, 0) + 1
            jaccards.append(result.jaccard)
            inliers.append(result.inlier_share)
        if on_result is not None:
            on_result(result)

    try:
        if jobs == 1:
            calibrator = _Calibrator(width_px, height_px, config)
            for item in items:
                handle(calibrator(*item))
        else:
            with ProcessPoolExecutor(jobs, initializer=_init_worker, initargs=(width_px, height_px, config)) as pool:
                for result in pool.map(_work, items, chunksize=4):
                    handle(result)
    finally:
        bar.close()
    summary["mean_self_jaccard"] = float(np.mean(jaccards)) if jaccards else 0.0
    summary["mean_inlier_share"] = float(np.mean(inliers)) if inliers else 0.0
    return summary


def draw_calibration(lines_norm: dict[str, np.ndarray], camera: Camera | None, width_px: int, height_px: int,
                     tau_px: float = 5.0, title: str = "") -> np.ndarray:
    """A picture of one calibrated frame (no image needed): (H, W, 3) uint8 BGR.

    Dark canvas, the camera's projected template in magenta, annotated points in green
    when within tau_px of their class (mirrored labelling allowed, as the metric does),
    red otherwise; the frame's JaC@tau in the corner.
    """
    import cv2

    from broadtrack_graph.metrics.soccernet import evaluate_frame
    from broadtrack_graph.detect.template_raster import template_mask

    canvas = np.full((height_px, width_px, 3), 35, np.uint8)
    text = title
    outcome = {}
    if camera is not None:
        canvas[template_mask(camera, TemplateCurves(), width_px, height_px, 1)] = (200, 0, 200)
        score = evaluate_frame(lines_norm, camera, width_px, height_px, (tau_px,))
        outcome = score.distances[tau_px]
        text += f"  JaC@{tau_px:g} {score.jac[tau_px]:.2f}" + (" (mirrored)" if score.mirrored[tau_px] else "")
    else:
        text += "  no camera"
    scale = np.array([width_px - 1, height_px - 1], dtype=float)
    from broadtrack_graph.geometry.pitch import MIRRORED_CLASS

    for name, points in lines_norm.items():
        distances = outcome.get(name, outcome.get(MIRRORED_CLASS.get(name, name)))
        for k, (u, v) in enumerate(np.asarray(points) * scale):
            good = distances is not None and k < len(distances) and distances[k] < tau_px
            cv2.circle(canvas, (int(round(u)), int(round(v))), 3, (0, 220, 0) if good else (0, 0, 255), -1)
    cv2.putText(canvas, text, (8, 22), cv2.FONT_HERSHEY_SIMPLEX, 0.6, (255, 255, 255), 1, cv2.LINE_AA)
    return canvas
