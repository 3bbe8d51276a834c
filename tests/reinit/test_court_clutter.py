"""The court model on grass full of lines that are no pitch's: a net's mesh, a striped kit, stray strokes, rings.

A frame whose lines form no pitch must get no camera the tracker takes (its confidence under the court model's bar,
:func:`~broadtrack_graph.track.frame_tries.court_accept_at`), however many hypotheses its lines make.
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateSampling, fitting_curves

PITCH = PitchTemplate()
W, H = 1280, 720
PAINT = (235, 235, 235)


def _grass(rng: np.random.Generator) -> np.ndarray:
    """(H, W, 3) BGR mown-green grass with a little noise."""
    image = np.full((H, W, 3), (40, 120, 50), np.float64) + rng.normal(0.0, 4.0, (H, W, 3))
    return np.clip(image, 0, 255).astype(np.uint8)


def _cluttered(kind: str) -> np.ndarray:
    """Grass drawn over with lines of ``kind`` (every line 2 px wide, bright as paint)."""
    rng = np.random.default_rng(7)
    image = _grass(rng)
    if kind == "net":  # two families of parallel strands, 24 px apart
        for x in range(0, W, 24):
            cv2.line(image, (x, 0), (x + 200, H), PAINT, 2)
        for y in range(0, H, 24):
            cv2.line(image, (0, y), (W, y + 60), PAINT, 2)
    elif kind == "stripes":  # a striped kit filling the frame
        for x in range(0, W, 16):
            cv2.rectangle(image, (x, 0), (x + 7, H), PAINT, -1)
    elif kind == "strokes":  # 200 straight strokes in every direction
        for _ in range(200):
            start = rng.integers(0, (W, H), 2)
            end = start + rng.integers(-300, 300, 2)
            cv2.line(image, tuple(int(v) for v in start), tuple(int(v) for v in end), PAINT, 2)
    elif kind == "rings":  # 60 ellipses of every size and tilt
        for _ in range(60):
            centre = tuple(int(v) for v in rng.integers(0, (W, H), 2))
            axes = (int(rng.integers(20, 300)), int(rng.integers(10, 120)))
            cv2.ellipse(image, centre, axes, float(rng.uniform(0.0, 180.0)), 0, 360, PAINT, 2)
    return image


@pytest.mark.parametrize("kind", ["net", "stripes", "strokes", "rings"])
def test_grass_full_of_lines_that_are_no_pitchs_gets_no_camera_the_tracker_takes(kind, one_opencv_thread):
    from broadtrack_graph.detect.weightfree import WeightFreeDetector
    from broadtrack_graph.reinit.court import court_reinit
    from broadtrack_graph.reinit.frame import frame_confidence
    from broadtrack_graph.track.config import TrackingConfig
    from broadtrack_graph.track.frame_tries import court_accept_at
    from broadtrack_graph.types.observations import FrameObservations

    detections = WeightFreeDetector(PITCH).detect(_cluttered(kind))
    curves = fitting_curves(PITCH)
    result = court_reinit(detections, (W, H), curves)
    assert detections.marking_mask is not None and detections.marking_mask.any()  # the lines are taken for paint
    if result.camera is not None:
        confidence = frame_confidence(result.camera, FrameObservations(0, W, H), detections, curves,
                                      TemplateSampling(PITCH))
        assert confidence < court_accept_at(TrackingConfig(), result), (kind, confidence, result.reason)
    else:
        assert result.reason  # and it says why
