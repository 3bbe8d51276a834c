"""Per-frame observations as plain data: what the front end produces and the graph consumes.

Everything is in pixels of the frame's own resolution (width_px x height_px),
principal point at the centre. No images, no I/O: the graph is testable without them.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace

import numpy as np


@dataclass
class KeypointObservations:
    """Labelled image points with known pitch positions.

    uv_px: (N, 2) pixels.
    points_w: (N, 3) metres, pitch frame (z down).
    confidence: (N,) in [0, 1].
    names: N keypoint names (template names, or "" for points given by coordinates).
    """

    uv_px: np.ndarray
    points_w: np.ndarray
    confidence: np.ndarray
    names: list[str] = field(default_factory=list)

    def __len__(self) -> int:
        return len(self.uv_px)


@dataclass
class FlowMatches:
    """Optical-flow matches between frame t-1 and frame t.

    uv_prev_px: (N, 2) pixels in frame t-1; uv_cur_px: (N, 2) the same ground points in frame t.
    """

    uv_prev_px: np.ndarray
    uv_cur_px: np.ndarray

    def __len__(self) -> int:
        return len(self.uv_prev_px)


@dataclass
class FrameObservations:
    """What is known about one frame.

    frame_index: position in the clip (0-based).
    width_px, height_px: image size the coordinates refer to.
    lines_px: class name -> (N, 2) pixels on that marking (SoccerNet class names).
    keypoints: labelled keypoints, or None.
    flow: matches from the previous frame, or None (first frame, after a cut, no images).
    marking_mask: (H, W) bool map of all detected markings, or None.
    player_boxes_px: (M, 4) [x0, y0, x1, y1] pixels, or None.
    """

    frame_index: int
    width_px: int
    height_px: int
    lines_px: dict[str, np.ndarray] = field(default_factory=dict)
    keypoints: KeypointObservations | None = None
    flow: FlowMatches | None = None
    marking_mask: np.ndarray | None = None
    player_boxes_px: np.ndarray | None = None

    @property
    def line_point_count(self) -> int:
        return int(sum(len(p) for p in self.lines_px.values()))

    @property
    def is_empty(self) -> bool:
        """True when the frame carries no measurement at all (a cut-away, a close-up)."""
        return self.line_point_count == 0 and not self.keypoints and not self.flow

    def rescaled(self, width_px: int, height_px: int) -> "FrameObservations":
        """The same observations at another resolution (coordinates scale with the width; pixel centres kept).

        The marking mask is dropped (it stays at the detector's size).
        """
        s = width_px / self.width_px

        def scale(uv_px: np.ndarray) -> np.ndarray:
            return (uv_px + 0.5) * s - 0.5

        kp = self.keypoints
        if kp is not None:
            kp = replace(kp, uv_px=scale(kp.uv_px))
        flow = self.flow
        if flow is not None:
            flow = replace(flow, uv_prev_px=scale(flow.uv_prev_px), uv_cur_px=scale(flow.uv_cur_px))
        return replace(
            self, width_px=width_px, height_px=height_px,
            lines_px={n: scale(p) for n, p in self.lines_px.items()}, keypoints=kp, flow=flow, marking_mask=None,
            player_boxes_px=None if self.player_boxes_px is None else self.player_boxes_px * s,
        )
