"""The homography-ground-truth protocol (TS-WorldCup style) for cameras and homographies: numbers only.

An estimate of a frame is anything that maps ground-plane points to pixels: a
:class:`~broadtrack_graph.geometry.camera.Camera` (distortion included) or a (3, 3)
homography (metres -> pixels). The ground truth is a homography per frame. Figures:

- ``iou_part``: on a top-view raster of the pitch (default 0.5 m cells), the cells whose
  centre the GT sees inside the image against those the estimate sees there; IoU.
- ``iou_whole``: the same with the image extended by ``extend`` times its size on every side,
  so that the whole pitch usually counts (the estimate far from the view is penalised).
- ``reprojection_px``: ground points on a 1 m grid over the pitch that the GT sees inside the
  image, projected by the estimate and by the GT; mean pixel distance.
- ``jitter_px``: RMS over points and frame triples of the second difference in time of
  (estimate - GT) image positions, on the grid points the GT sees inside the image in the
  middle frame of the triple (only triples of consecutive frames that all have an estimate).

Frames without an estimate count 0 in the IoUs and are left out of the pixel figures.
Pitch frame: SoccerNet (origin at the centre spot, x towards the right goal, +y towards the
near touchline, z down); the ground is z = 0.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera


@dataclass(frozen=True)
class ProtocolConfig:
    """Settings of the protocol."""

    length_m: float = 105.0  # pitch length (x extent)
    width_m: float = 68.0  # pitch width (y extent)
    iou_cell_m: float = 0.5  # top-view raster cell for the IoUs
    grid_step_m: float = 1.0  # ground grid for the reprojection error and the jitter
    extend: float = 1.0  # iou_whole: image extended by this many widths/heights on each side


def ground_grid(step_m: float, length_m: float = 105.0, width_m: float = 68.0) -> np.ndarray:
    """(N, 2) metres: cell centres of a step_m grid over the pitch (x, y), origin at the centre spot."""
    xs = np.arange(-length_m / 2 + step_m / 2, length_m / 2, step_m)
    ys = np.arange(-width_m / 2 + step_m / 2, width_m / 2, step_m)
    gx, gy = np.meshgrid(xs, ys)
    return np.column_stack([gx.ravel(), gy.ravel()])


def project_ground(estimate, points_xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Pixels of ground points under an estimate.

    Args:
        estimate: a Camera, or a (3, 3) homography metres -> pixels.
        points_xy: (N, 2) metres on the ground plane.

    Returns:
        uv_px: (N, 2) pixels (NaN where invalid); valid: (N,) in front of the camera / positive
        homogeneous scale.
    """
    points_xy = np.asarray(points_xy, float).reshape(-1, 2)
    if isinstance(estimate, Camera):
        uv, front = estimate.project(np.column_stack([points_xy, np.zeros(len(points_xy))]))
        return np.where(front[:, None], uv, np.nan), front
    H = np.asarray(estimate, float).reshape(3, 3)
    h = np.column_stack([points_xy, np.ones(len(points_xy))]) @ H.T
    valid = h[:, 2] > 1e-9 * np.abs(h).max(initial=1.0)
    uv = np.full((len(points_xy), 2), np.nan)
    uv[valid] = h[valid, :2] / h[valid, 2:3]
    return uv, valid


def _inside(uv: np.ndarray, valid: np.ndarray, width_px: int, height_px: int, extend: float = 0.0) -> np.ndarray:
    x0, y0 = -extend * width_px, -extend * height_px
    x1, y1 = (1 + extend) * width_px, (1 + extend) * height_px
    with np.errstate(invalid="ignore"):
        return valid & (uv[:, 0] >= x0) & (uv[:, 0] <= x1) & (uv[:, 1] >= y0) & (uv[:, 1] <= y1)


def _iou(a: np.ndarray, b: np.ndarray) -> float:
    union = int((a | b).sum())
    return float((a & b).sum() / union) if union else 0.0


def frame_figures(estimate, H_gt: np.ndarray, width_px: int, height_px: int,
                  config: ProtocolConfig = ProtocolConfig()) -> dict:
    """IoU_part, IoU_whole and the reprojection error of one frame (estimate None: IoUs 0, error None)."""
    cells = ground_grid(config.iou_cell_m, config.length_m, config.width_m)
    uv_gt, ok_gt = project_ground(H_gt, cells)
    seen_gt = _inside(uv_gt, ok_gt, width_px, height_px)
    seen_gt_whole = _inside(uv_gt, ok_gt, width_px, height_px, config.extend)
    if estimate is None:
        return {"iou_part": 0.0, "iou_whole": 0.0, "reprojection_px": None}
    uv_est, ok_est = project_ground(estimate, cells)
    iou_part = _iou(seen_gt, _inside(uv_est, ok_est, width_px, height_px))
    iou_whole = _iou(seen_gt_whole, _inside(uv_est, ok_est, width_px, height_px, config.extend))
    grid = ground_grid(config.grid_step_m, config.length_m, config.width_m)
    g_uv, g_ok = project_ground(H_gt, grid)
    visible = _inside(g_uv, g_ok, width_px, height_px)
    e_uv, e_ok = project_ground(estimate, grid[visible])
    error = np.where(e_ok, np.linalg.norm(e_uv - g_uv[visible], axis=1), np.nan)
    reprojection = float(np.nanmean(error)) if np.isfinite(error).any() else None
    return {"iou_part": iou_part, "iou_whole": iou_whole, "reprojection_px": reprojection}


def jitter_px(estimates: Mapping[int, object], gt: Mapping[int, np.ndarray], width_px: int, height_px: int,
              config: ProtocolConfig = ProtocolConfig()) -> float | None:
    """RMS second difference in time of (estimate - GT) pixels; None without any complete triple.

    Args:
        estimates: frame index -> Camera / (3, 3) homography / None.
        gt: frame index -> (3, 3) GT homography.
    """
    grid = ground_grid(config.grid_step_m, config.length_m, config.width_m)
    squares, count = 0.0, 0
    for t in sorted(gt):
        triple = (t - 1, t, t + 1)
        if any(estimates.get(i) is None or i not in gt for i in triple):
            continue
        g_uv, g_ok = project_ground(gt[t], grid)
        points = grid[_inside(g_uv, g_ok, width_px, height_px)]
        offsets = []
        for i in triple:
            e_uv, _ = project_ground(estimates[i], points)
            gi_uv, _ = project_ground(gt[i], points)
            offsets.append(e_uv - gi_uv)
        second = offsets[2] - 2 * offsets[1] + offsets[0]
        norms = np.linalg.norm(second, axis=1)
        norms = norms[np.isfinite(norms)]
        squares += float(np.sum(norms**2))
        count += len(norms)
    return float(np.sqrt(squares / count)) if count else None


def clip_figures(estimates: Mapping[int, object], gt: Mapping[int, np.ndarray], width_px: int, height_px: int,
                 config: ProtocolConfig = ProtocolConfig()) -> dict:
    """The protocol over a clip: completeness, mean IoU_part / IoU_whole (missing frames 0),
    mean and median reprojection error (frames with an estimate), jitter. Frames = the GT's frames."""
    per_frame = [frame_figures(estimates.get(t), gt[t], width_px, height_px, config) for t in sorted(gt)]
    errors = [f["reprojection_px"] for f in per_frame if f["reprojection_px"] is not None]
    with_estimate = sum(estimates.get(t) is not None for t in gt)
    return {
        "frames": len(gt),
        "completeness": with_estimate / len(gt) if gt else 0.0,
        "iou_part": float(np.mean([f["iou_part"] for f in per_frame])) if per_frame else 0.0,
        "iou_whole": float(np.mean([f["iou_whole"] for f in per_frame])) if per_frame else 0.0,
        "reprojection_px": float(np.mean(errors)) if errors else None,
        "reprojection_median_px": float(np.median(errors)) if errors else None,
        "jitter_px": jitter_px(estimates, gt, width_px, height_px, config),
    }


def fit_keypoint_homography(uv_px: np.ndarray, points_xy: np.ndarray, threshold_px: float = 5.0) -> np.ndarray | None:
    """The per-frame baseline: a RANSAC homography (metres -> pixels) from one frame's keypoints.

    Args:
        uv_px: (N, 2) pixels; points_xy: (N, 2) ground metres. None when N < 4 or the fit fails.
    """
    uv_px = np.asarray(uv_px, np.float64).reshape(-1, 2)
    points_xy = np.asarray(points_xy, np.float64).reshape(-1, 2)
    if len(uv_px) < 4:
        return None
    H, _ = cv2.findHomography(points_xy, uv_px, cv2.RANSAC, threshold_px)
    return None if H is None or not np.isfinite(H).all() else H
