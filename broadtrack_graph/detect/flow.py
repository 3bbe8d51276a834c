"""Optical flow between consecutive frames: pyramidal Lucas-Kanade on a grid, checked both ways.

Grid points of frame t-1 are tracked into frame t and back; a match is kept when it
returns within ``fb_max_px`` of where it started, lies on the projected pitch of the
previous camera (or on the field mask when no camera is known) and away from
players. The tracker back-projects the t-1 point to the ground with camera t-1
(:func:`ground_points` here, factors.flow in the graph). No I/O.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.shots.repeats import reduced_grey
from broadtrack_graph.types.observations import FlowMatches


@dataclass(frozen=True)
class FlowConfig:
    """Settings of :func:`grid_flow`."""

    work_width_px: int = 640  # flow runs on grey frames resized to this width
    grid_step_px: int = 28  # grid spacing at the working width
    window_px: int = 15  # Lucas-Kanade window
    pyramid_levels: int = 3
    fb_max_px: float = 0.5  # forward-backward error bound, working pixels
    pitch_margin_m: float = 1.0  # matches must back-project inside the pitch grown by this
    # Between two frames of a camera on a tripod every grass point moves by one homography: the matches it leaves
    # further than this (working pixels) are dropped (0: kept), the pixels of an overlay that stays put while the
    # camera moves among them (a score bug before the graphics mask has learned it, detect.graphics)
    consensus_px: float = 3.0
    # Each working image is divided by its own Gaussian blur of this sigma (working pixels; 0: not): shading that
    # stays put in the frame (lens vignetting, exposure changes) is taken out, or where motion blur leaves little
    # texture it holds the matches back towards no motion
    shading_sigma_px: float = 32.0
    shading_gain: float = 512.0  # grey levels per unit of relative brightness after the division (around 128)


class FlowFrame:
    """A frame prepared once for flow: its grey working image :attr:`grey` (h, w) uint8.

    ``shading``: the flow's settings when the shading is still to be taken out of ``grey`` (``_without_shading``);
    it is, when the grey image is first read: by the side that tracks the frame's flow first (the process preparing
    the frames when it is ahead, else the tracking; the same numbers either way). None: ``grey`` is final.
    (OpenCV 5's Python binding does not accept prebuilt pyramids, so LK builds them.)
    """

    def __init__(self, grey: np.ndarray, shading: FlowConfig | None = None) -> None:
        self._grey = grey if shading is None else None
        self._with_shading = None if shading is None else grey
        self._shading = shading

    @property
    def grey(self) -> np.ndarray:
        if self._grey is None:
            self._grey, self._with_shading = _without_shading(self._with_shading, self._shading), None
        return self._grey

    @property
    def shape(self) -> tuple[int, int]:
        return (self._grey if self._grey is not None else self._with_shading).shape


def prepare(image_bgr: np.ndarray, config: FlowConfig = FlowConfig(), grey: np.ndarray | None = None,
            reduced_bgr: np.ndarray | None = None) -> FlowFrame:
    """Grey working image for :func:`grid_flow` (compute once per frame and reuse).

    grey: the frame's :func:`~broadtrack_graph.shots.repeats.reduced_grey` at the flow's working width when
    already made (the repeat test's, at the same width); None (or another width): made here, from ``reduced_bgr``
    when given (as for :func:`~broadtrack_graph.shots.repeats.reduced_grey`).
    """
    h, w = image_bgr.shape[:2]
    if grey is None or grey.shape[1] != min(config.work_width_px, w):
        grey = reduced_grey(image_bgr, config.work_width_px, reduced_bgr)
    return FlowFrame(grey, config if config.shading_sigma_px > 0 else None)  # the shading taken out when first read


def _without_shading(grey: np.ndarray, config: FlowConfig) -> np.ndarray:
    """(h, w) uint8: the grey image relative to its local mean (a Gaussian of ``shading_sigma_px``), around 128.

    The local mean is smooth, so it is taken on the image reduced by a quarter of the sigma and scaled back up
    (a tenth of the cost of the full-size blur).
    """
    h, w = grey.shape
    image = grey.astype(np.float32) + 1.0
    factor = max(1, int(config.shading_sigma_px // 4))
    small = cv2.resize(image, (max(1, w // factor), max(1, h // factor)), interpolation=cv2.INTER_AREA)
    small = cv2.GaussianBlur(small, (0, 0), config.shading_sigma_px / factor)
    local = cv2.resize(small, (w, h), interpolation=cv2.INTER_LINEAR)
    relative = cv2.divide(image, local) - 1.0
    return np.clip(128.0 + config.shading_gain * relative, 0, 255).astype(np.uint8)


def ground_points(camera: Camera, uv_px: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Back-project pixels of a frame to the pitch plane z = 0 with its camera: (points_w (N, 3), hits (N,))."""
    return camera.ground_intersection(uv_px)


def grid_flow(prev_frame: FlowFrame, cur_frame: FlowFrame, width_px: int, height_px: int,
              prev_camera: Camera | None = None, keep_mask: np.ndarray | None = None,
              config: FlowConfig = FlowConfig(), pitch_half_size_m=(52.5, 34.0)) -> FlowMatches:
    """Grid Lucas-Kanade matches from frame t-1 to frame t, in full-frame pixels.

    Args:
        prev_frame, cur_frame: prepared frames from :func:`prepare` (same config).
        width_px, height_px: full frame size (the matches are returned at it).
        prev_camera: camera t-1 (full size); matches must back-project onto the pitch. None: no such check.
        keep_mask: bool mask, True where matches are allowed (field, not players), at the frame size or
            a reduced size of the same aspect ratio; or None.

    Returns:
        FlowMatches (uv_prev_px, uv_cur_px), possibly empty.
    """
    p0, p1, good, scale = _tracked_grid(prev_frame, cur_frame, width_px, height_px, prev_camera, keep_mask, config,
                                        pitch_half_size_m)
    if len(p0) == 0:
        return FlowMatches(np.zeros((0, 2)), np.zeros((0, 2)))
    return _consistent(((p0[good] + 0.5) / scale - 0.5).astype(float), ((p1[good] + 0.5) / scale - 0.5).astype(float),
                       config.consensus_px / scale)


def _tracked_grid(prev_frame: FlowFrame, cur_frame: FlowFrame, width_px: int, height_px: int,
                  prev_camera: Camera | None, keep_mask: np.ndarray | None, config: FlowConfig, pitch_half_size_m):
    """(p0, p1, good, scale): the grid points kept (working pixels, float32), where LK took them, which matches
    pass the checks, and working / frame pixels."""
    h, w = prev_frame.shape
    scale = w / width_px
    step = config.grid_step_px
    xs, ys = np.meshgrid(np.arange(step / 2, w, step), np.arange(step / 2, h, step))
    p0 = np.column_stack([xs.ravel(), ys.ravel()]).astype(np.float32)
    full0 = (p0 + 0.5) / scale - 0.5
    ok = np.ones(len(p0), dtype=bool)
    if keep_mask is not None:
        ok &= _mask_at(keep_mask, full0, width_px, height_px)
    if prev_camera is not None and ok.any():
        ok[np.flatnonzero(ok)[~_on_pitch(prev_camera, full0[ok], config, pitch_half_size_m)]] = False
    p0 = p0[ok]
    if len(p0) == 0:
        return p0, p0, np.zeros(0, bool), scale
    params = dict(winSize=(config.window_px, config.window_px), maxLevel=config.pyramid_levels,
                  criteria=(cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_COUNT, 20, 0.03))
    p1, st1, _ = cv2.calcOpticalFlowPyrLK(prev_frame.grey, cur_frame.grey, p0.reshape(-1, 1, 2), None, **params)
    p0b, st2, _ = cv2.calcOpticalFlowPyrLK(cur_frame.grey, prev_frame.grey, p1, None, **params)
    p1, p0b = p1.reshape(-1, 2), p0b.reshape(-1, 2)
    good = (st1.ravel() == 1) & (st2.ravel() == 1) & (np.linalg.norm(p0b - p0, axis=1) <= config.fb_max_px)
    good &= (p1[:, 0] >= 0) & (p1[:, 0] < w) & (p1[:, 1] >= 0) & (p1[:, 1] < h)
    if keep_mask is not None and good.any():
        good &= _mask_at(keep_mask, (p1 + 0.5) / scale - 0.5, width_px, height_px)
    return p0, p1, good, scale


def flow_keep_mask(detections) -> np.ndarray | None:
    """Where a frame's flow may start: its field, off the players (a Detections' masks; None: anywhere)."""
    keep = detections.field_mask
    if keep is not None and detections.player_mask is not None:
        keep = keep & ~detections.player_mask
    return keep


@dataclass(frozen=True)
class FlowCandidates:
    """What :func:`grid_flow` finds before the previous camera's pitch check: computable ahead, before camera t-1
    is known (the tracker does it in the thread that decodes the frames).

    prev_frame: the prepared frame t-1 they start from; keep_mask: the keep mask used (or None);
    width_px, height_px: the frame size the pixels are at.
    uv_prev_px, uv_cur_px: (N, 2) float32 full-frame pixels of the grid points tracked both ways, grid order.
    """

    prev_frame: FlowFrame
    keep_mask: np.ndarray | None
    width_px: int
    height_px: int
    uv_prev_px: np.ndarray
    uv_cur_px: np.ndarray


def flow_candidates(prev_frame: FlowFrame, cur_frame: FlowFrame, width_px: int, height_px: int,
                    keep_mask: np.ndarray | None = None, config: FlowConfig = FlowConfig()) -> FlowCandidates:
    """:func:`grid_flow` without a previous camera, its matches kept for :func:`on_pitch`.

    Lucas-Kanade tracks every point on its own, so ``on_pitch(flow_candidates(...), camera)`` gives exactly
    ``grid_flow(..., camera, ...)`` (at the cost of tracking the grid points off the pitch too).
    """
    p0, p1, good, scale = _tracked_grid(prev_frame, cur_frame, width_px, height_px, None, keep_mask, config,
                                        (0.0, 0.0))
    return FlowCandidates(prev_frame, keep_mask, width_px, height_px, (p0[good] + 0.5) / scale - 0.5,
                          (p1[good] + 0.5) / scale - 0.5)


def on_pitch(candidates: FlowCandidates, prev_camera: Camera, config: FlowConfig = FlowConfig(),
             pitch_half_size_m=(52.5, 34.0)) -> FlowMatches:
    """The candidates whose frame t-1 point back-projects onto the pitch (grown by ``pitch_margin_m``) through
    camera t-1: the matches :func:`grid_flow` gives with that camera."""
    uv0, uv1 = candidates.uv_prev_px, candidates.uv_cur_px
    if not len(uv0):
        return FlowMatches(np.zeros((0, 2)), np.zeros((0, 2)))
    inside = _on_pitch(prev_camera, uv0, config, pitch_half_size_m)
    scale = candidates.prev_frame.shape[1] / candidates.width_px
    return _consistent(uv0[inside].astype(float), uv1[inside].astype(float), config.consensus_px / scale)


MIN_CONSENSUS_MATCHES = 8
"""Fewer matches are kept as they are: too few to tell the camera's motion from an overlay's."""


def _consistent(uv0: np.ndarray, uv1: np.ndarray, threshold_px: float) -> FlowMatches:
    """The matches (N, 2) frame pixels within ``threshold_px`` of the homography most of them follow (RANSAC; OpenCV
    seeds it alike on every call: the same matches give the same result); all of them when ``threshold_px`` is 0 or
    there are fewer than :data:`MIN_CONSENSUS_MATCHES`."""
    if threshold_px <= 0 or len(uv0) < MIN_CONSENSUS_MATCHES:
        return FlowMatches(uv0, uv1)
    _, inliers = cv2.findHomography(uv0, uv1, cv2.RANSAC, threshold_px)
    if inliers is None:
        return FlowMatches(uv0, uv1)
    keep = inliers.ravel().astype(bool)
    return FlowMatches(uv0[keep], uv1[keep])


def _on_pitch(camera: Camera, uv_px: np.ndarray, config: FlowConfig, pitch_half_size_m) -> np.ndarray:
    ground, hits = camera.ground_intersection(uv_px)
    return hits & (np.abs(ground[:, 0]) <= pitch_half_size_m[0] + config.pitch_margin_m) & (
        np.abs(ground[:, 1]) <= pitch_half_size_m[1] + config.pitch_margin_m)


def _mask_at(mask: np.ndarray, uv_px: np.ndarray, width_px: int, height_px: int) -> np.ndarray:
    """Values of a (possibly reduced-size) mask at full-frame pixels."""
    mh, mw = mask.shape
    c = np.clip(np.round((uv_px[:, 0] + 0.5) * mw / width_px - 0.5).astype(int), 0, mw - 1)
    r = np.clip(np.round((uv_px[:, 1] + 0.5) * mh / height_px - 0.5).astype(int), 0, mh - 1)
    return mask[r, c]
