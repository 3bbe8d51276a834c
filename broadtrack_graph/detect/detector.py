"""The detector interface: what every field-marking detector returns for one frame.

A detector is any object with ``detect(image_bgr, predicted=None) -> Detections``
(:class:`FieldDetector`). ``predicted`` is the tracker's predicted camera with its
uncertainty; detectors that need it to name the markings (the weight-free one)
use it, learned ones ignore it. :meth:`Detections.to_observations` turns the result
into the graph's :class:`~broadtrack_graph.types.observations.FrameObservations`.

All coordinates are pixels of the frame that was passed in (principal point at the
centre). No I/O.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Protocol

import numpy as np

from broadtrack_graph.detect.motion_blur import MotionBlur
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.types.observations import FlowMatches, FrameObservations, KeypointObservations


@dataclass(frozen=True)
class PredictedCamera:
    """The tracker's prediction for the current frame.

    camera: predicted camera at the frame's resolution.
    uncertainty_px: how far (pixels, 1 sigma) the projected template may be from the truth;
        the labelling gate of the weight-free detector grows with it.
    """

    camera: Camera
    uncertainty_px: float = 5.0


@dataclass
class Detections:
    """One frame's detections.

    width_px, height_px: frame size.
    lines_px: class name -> (N, 2) pixels on that marking (only classes that were named).
    marking_points_px: (M, 2) pixels on any marking, named or not (centre-line points).
    keypoints: labelled keypoints, or None.
    marking_mask: bool map of all markings; the masks may be at a reduced working size
        (same aspect ratio; :meth:`full_size` scales one to (H, W)).
    player_boxes_px: (P, 4) [x0, y0, x1, y1] pixels.
    player_mask: bool map of players, or None.
    field_mask: bool map of the playing surface, or None.
    motion_blur: the frame's straight motion blur (:class:`~broadtrack_graph.detect.motion_blur.MotionBlur`, its
        length in frame pixels), or None (none found, or a detector that does not look).
    info: detector-specific diagnostics (timings, thresholds).
    """

    width_px: int
    height_px: int
    lines_px: dict[str, np.ndarray] = field(default_factory=dict)
    marking_points_px: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))
    keypoints: KeypointObservations | None = None
    marking_mask: np.ndarray | None = None
    player_boxes_px: np.ndarray = field(default_factory=lambda: np.zeros((0, 4)))
    player_mask: np.ndarray | None = None
    field_mask: np.ndarray | None = None
    motion_blur: MotionBlur | None = None
    info: dict = field(default_factory=dict)

    def full_size(self, mask: np.ndarray | None) -> np.ndarray | None:
        """A mask of this frame scaled (nearest) to (height_px, width_px)."""
        if mask is None or mask.shape == (self.height_px, self.width_px):
            return mask
        return resize_mask(mask, self.width_px, self.height_px)

    def to_observations(self, frame_index: int, flow: FlowMatches | None = None,
                        with_marking_mask: bool = True) -> FrameObservations:
        """The graph's FrameObservations for this frame (flow from :mod:`broadtrack_graph.detect.flow`).

        with_marking_mask: give the observations the marking map at the frame size; False: none (the tracker reads
        the map from the detections, at the working size: scaling it up costs about a millisecond a frame).
        """
        return FrameObservations(
            frame_index=frame_index, width_px=self.width_px, height_px=self.height_px,
            lines_px={name: np.asarray(points, float) for name, points in self.lines_px.items() if len(points)},
            keypoints=self.keypoints, flow=flow,
            marking_mask=self.full_size(self.marking_mask) if with_marking_mask else None,
            player_boxes_px=np.asarray(self.player_boxes_px, float).reshape(-1, 4),
        )


class FieldDetector(Protocol):
    """What the tracker calls on every frame."""

    def detect(self, image_bgr: np.ndarray, predicted: PredictedCamera | None = None) -> Detections:
        """Detect the field markings of one (H, W, 3) uint8 BGR frame."""
        ...


def check_image(image_bgr: np.ndarray) -> np.ndarray:
    """Raise a ValueError unless the image is (H, W, 3) uint8 (BGR)."""
    image = np.asarray(image_bgr)
    if image.ndim != 3 or image.shape[2] != 3 or image.dtype != np.uint8:
        raise ValueError(f"image_bgr: expected (H, W, 3) uint8, got {image.shape} {image.dtype}")
    return image


def resize_mask(mask: np.ndarray, width_px: int, height_px: int) -> np.ndarray:
    """Nearest-neighbour resize of a bool mask to (height_px, width_px)."""
    import cv2

    return cv2.resize(np.asarray(mask, np.uint8), (int(width_px), int(height_px)), interpolation=cv2.INTER_NEAREST) > 0


def draw_detections(image_bgr: np.ndarray, detections: Detections, camera: Camera | None = None,
                    curves=None) -> np.ndarray:
    """A picture of what a detector found (no I/O): a copy of the frame with

    the field tinted, unnamed marking points in yellow, named points coloured per class
    (legend at the top left), player boxes in blue and, when a camera is given, the
    projected template in thin magenta lines.
    """
    import cv2

    from broadtrack_graph.geometry.pitch import LINE_CLASSES

    out = image_bgr.copy()
    H, W = out.shape[:2]
    if detections.field_mask is not None:
        field = detections.full_size(detections.field_mask)
        out[~field] = (out[~field] * 0.45).astype(np.uint8)
    if camera is not None:
        from broadtrack_graph.detect.template_raster import template_mask

        if curves is None:
            from broadtrack_graph.geometry.template import TemplateCurves

            curves = TemplateCurves()
        out[template_mask(camera, curves, W, H, max(1, W // 960))] = (255, 0, 255)
    dot = max(1, W // 1280)
    for u, v in np.round(detections.marking_points_px).astype(int):
        cv2.circle(out, (int(u), int(v)), dot, (0, 255, 255), -1)
    rng = np.random.default_rng(0)
    palette = {name: tuple(int(c) for c in rng.integers(60, 256, 3)) for name in LINE_CLASSES}
    radius = max(2, W // 640)
    for row, (name, points) in enumerate(sorted(detections.lines_px.items())):
        colour = palette.get(name, (0, 0, 255))
        for u, v in np.round(points).astype(int):
            cv2.circle(out, (int(u), int(v)), radius, colour, -1)
        cv2.putText(out, name, (10, 22 + 20 * row), cv2.FONT_HERSHEY_SIMPLEX, 0.55, colour, 2, cv2.LINE_AA)
    for x0, y0, x1, y1 in np.round(np.asarray(detections.player_boxes_px).reshape(-1, 4)).astype(int):
        cv2.rectangle(out, (int(x0), int(y0)), (int(x1), int(y1)), (255, 80, 0), 1)
    return out
