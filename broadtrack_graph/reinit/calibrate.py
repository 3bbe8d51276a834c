"""Single-frame calibration from per-class marking points (SoccerNet annotations as detections).

Each frame's labelled line points are treated as the output of a perfect line
detector: :func:`broadtrack_graph.reinit.lines.reinit_from_lines` forms several
hypotheses (homography of the straight ground lines, global pan/tilt/f search at the
default tripod positions and their mirrors), refines each and keeps the best by the
per-class score. No image is needed. No I/O here; the set-level job (every annotated
frame, over worker processes) is :func:`broadtrack_graph.actions.calibrate.calibrate_annotation_set`,
which runs :func:`init_worker` once per process and :func:`calibrate_item` per frame.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves, TemplateSampling
from broadtrack_graph.io.annotations import annotation_to_pixels
from broadtrack_graph.reinit.lines import ReinitConfig, reinit_from_lines
from broadtrack_graph.reinit.scoring import ReinitResult

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


def init_worker(width_px: int, height_px: int, config: ReinitConfig) -> None:
    """Build this process's calibrator (template samplings) once, before its first frame."""
    global _WORKER
    _WORKER = _Calibrator(width_px, height_px, config)


def calibrate_item(item: tuple[str, dict[str, np.ndarray]]) -> FrameCalibration:
    """Calibrate one (frame id, class name -> (M, 2) normalised points) with this process's calibrator."""
    return _WORKER(*item)
