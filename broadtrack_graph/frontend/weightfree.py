"""The default, weight-free field-marking detector (no learned model).

Pipeline for one BGR frame, run at a reduced working width (960 px by default) and
mapped back to the frame's pixels:

1. grass: HSV thresholds on green; the playing field is the filled outline of the
   large grass regions (so lines and players inside it belong to it);
2. players and clutter: non-grass blobs inside the field that survive an opening
   larger than a line's width and look like upright bodies -> boxes and a mask;
3. marking ridges: white top-hat of the grey image, inside the field, away from
   players; each candidate pixel is moved to the sub-pixel centre of the ridge with
   Steger's Hessian method (offset along the line normal, kept when within half a
   pixel), which gives centre-line points with no thinning step;
4. naming: with a predicted camera, the template is projected and every ridge point
   takes the class of the nearest projected marking (one distance transform with
   labels) when it is within a gate of ``gate_px + gate_sigmas * uncertainty_px``;
   without a prediction only the unnamed points and the marking map are returned
   (re-initialisation then works from the map, see reinit.reinit_from_mask).

No I/O.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import cv2
import numpy as np

from broadtrack_graph.camera import Camera
from broadtrack_graph.frontend.detector import Detections, PredictedCamera, check_image
from broadtrack_graph.frontend.linefit import TemplateCurves
from broadtrack_graph.frontend.meanshift import mean_shift_thin
from broadtrack_graph.pitch import LINE_CLASSES, PitchTemplate


@dataclass(frozen=True)
class WeightFreeConfig:
    """Settings of :class:`WeightFreeDetector` (pixel sizes at the working width)."""

    work_width_px: int = 960  # processing width; the frame is resized to it
    grass_hue_min: int = 30  # OpenCV hue (0..180) range of grass
    grass_hue_max: int = 95
    grass_min_saturation: int = 40
    grass_min_value: int = 30
    grass_reach_px: int = 4  # field pixels farther than this from grass are not field (boards, text)
    field_min_area_fraction: float = 0.02  # grass regions smaller than this share of the image are ignored
    tophat_kernel_px: int = 9  # white top-hat size: lines up to about this wide are kept
    tophat_threshold: float = 14.0  # grey levels above the local background
    support_window_px: int = 9  # a centre-line point needs min_support others in this window ...
    min_support: int = 7  # ... (a line crossing it gives about the window size; specks fewer)
    ridge_sigma_px: float = 1.0  # Gaussian scale of the Hessian
    ridge_min_curvature: float = 1.5  # -lambda_min of the smoothed top-hat (grey levels / px^2)
    player_open_px: int = 5  # opening that removes lines but keeps bodies
    player_min_area_px: int = 40  # smaller non-grass blobs are not players
    player_margin_px: int = 3  # ridge points this close to a player are dropped
    gate_px: float = 4.0  # naming gate at full resolution ...
    gate_sigmas: float = 2.5  # ... plus this many predicted uncertainties
    class_consistency_px: float = 2.0  # full-resolution band around a class's median distance to its prediction
    min_points_per_class: int = 4  # fewer named points: the class is dropped
    smoothing_px: float = 4.0  # mean-shift radius along a named marking (working pixels)
    point_spacing_px: float = 3.0  # named points are kept one per cell of this size (working pixels)


class WeightFreeDetector:
    """Field markings from colour and shape alone; names them with a predicted camera (module docstring).

    Args:
        pitch: the template used for naming.
        config: thresholds.
    """

    def __init__(self, pitch: PitchTemplate | None = None, config: WeightFreeConfig = WeightFreeConfig()):
        self.pitch = pitch or PitchTemplate()
        self.config = config
        self.curves = TemplateCurves(self.pitch, line_step_m=1.0, circle_step_m=0.5)
        k = config.tophat_kernel_px
        self._tophat_kernel = cv2.getStructuringElement(cv2.MORPH_RECT, (k, k))
        p = config.player_open_px
        self._open_kernel = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (p, p))

    # ----------------------------------------------------------------- steps

    def field_and_grass(self, small_bgr: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(grass, field) uint8 masks (0/255) at the working size; the field is the filled outline of the grass."""
        c = self.config
        hsv = cv2.cvtColor(small_bgr, cv2.COLOR_BGR2HSV)
        grass = cv2.inRange(hsv, (c.grass_hue_min, c.grass_min_saturation, c.grass_min_value), (c.grass_hue_max, 255, 255))
        h, w = grass.shape
        tiny = cv2.resize(grass, (w // 4, h // 4), interpolation=cv2.INTER_AREA)
        tiny = (tiny > 100).astype(np.uint8) * 255
        tiny = cv2.morphologyEx(tiny, cv2.MORPH_CLOSE, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (7, 7)))
        contours, _ = cv2.findContours(tiny, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_SIMPLE)
        filled = np.zeros_like(tiny)
        min_area = c.field_min_area_fraction * tiny.size
        big = [cnt for cnt in contours if cv2.contourArea(cnt) >= min_area]
        if big:
            cv2.drawContours(filled, big, -1, 255, thickness=cv2.FILLED)
        field = cv2.resize(filled, (w, h), interpolation=cv2.INTER_NEAREST)
        return grass, field

    def players(self, grass: np.ndarray, field: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """(boxes (P, 4) working pixels, mask uint8) of upright non-grass blobs inside the field."""
        c = self.config
        non_grass = cv2.bitwise_and(cv2.bitwise_not(grass), field)
        opened = cv2.morphologyEx(non_grass, cv2.MORPH_OPEN, self._open_kernel)
        count, labels, stats, _ = cv2.connectedComponentsWithStats(opened, connectivity=8)
        boxes, keep = [], np.zeros(count, dtype=bool)
        for i in range(1, count):
            x, y, w, h, area = stats[i]
            if area < c.player_min_area_px or h < 0.8 * w or h > 6 * w or area < 0.25 * w * h:
                continue
            keep[i] = True
            boxes.append((x, y, x + w, y + h))
        mask = keep[labels].astype(np.uint8) * 255
        if c.player_margin_px > 0 and boxes:
            m = 2 * c.player_margin_px + 1
            mask = cv2.dilate(mask, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (m, m)))
        return np.asarray(boxes, float).reshape(-1, 4), mask

    def ridges(self, small_bgr: np.ndarray, allowed: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Sub-pixel centre-line points (N, 2) (working pixels) and the candidate map (uint8)."""
        c = self.config
        grey = cv2.cvtColor(small_bgr, cv2.COLOR_BGR2GRAY)
        tophat = cv2.morphologyEx(grey, cv2.MORPH_TOPHAT, self._tophat_kernel)
        candidates = ((tophat > c.tophat_threshold) & (allowed > 0)).astype(np.uint8)
        ys, xs = np.nonzero(candidates)
        if len(xs) == 0:
            return np.zeros((0, 2)), candidates
        smooth = cv2.GaussianBlur(tophat.astype(np.float32), (0, 0), c.ridge_sigma_px)
        gx = cv2.Sobel(smooth, cv2.CV_32F, 1, 0, ksize=3, scale=1 / 8)[ys, xs]
        gy = cv2.Sobel(smooth, cv2.CV_32F, 0, 1, ksize=3, scale=1 / 8)[ys, xs]
        gxx = cv2.Sobel(smooth, cv2.CV_32F, 2, 0, ksize=3, scale=1 / 4)[ys, xs]
        gyy = cv2.Sobel(smooth, cv2.CV_32F, 0, 2, ksize=3, scale=1 / 4)[ys, xs]
        gxy = cv2.Sobel(smooth, cv2.CV_32F, 1, 1, ksize=3, scale=1 / 4)[ys, xs]
        half_diff = 0.5 * (gxx - gyy)
        root = np.sqrt(half_diff * half_diff + gxy * gxy)
        lam = 0.5 * (gxx + gyy) - root  # most negative eigenvalue: curvature across the line
        # Eigenvector of lam (across the line), robust form.
        nx = np.where(half_diff <= 0, gxy, lam - gyy)
        ny = np.where(half_diff <= 0, lam - gxx, gxy)
        norm = np.hypot(nx, ny)
        norm = np.where(norm < 1e-9, 1.0, norm)
        nx, ny = nx / norm, ny / norm
        with np.errstate(divide="ignore", invalid="ignore"):
            t = -(gx * nx + gy * ny) / lam
        ok = (lam < -c.ridge_min_curvature) & (np.abs(t * nx) <= 0.5) & (np.abs(t * ny) <= 0.5)
        # Markings are long: a centre-line point needs enough other centre-line points around it
        # (a line crossing the window gives about its width); specks of grass texture do not.
        centre = np.zeros_like(candidates)
        centre[ys[ok], xs[ok]] = 1
        k = c.support_window_px
        support = cv2.boxFilter(centre, cv2.CV_16U, (k, k), normalize=False)
        ok[ok] = support[ys[ok], xs[ok]] >= c.min_support
        points = np.column_stack([xs[ok] + t[ok] * nx[ok], ys[ok] + t[ok] * ny[ok]])
        return points, candidates

    def name_points(self, points_px: np.ndarray, predicted: PredictedCamera, scale: float,
                    size: tuple[int, int]) -> dict[str, np.ndarray]:
        """Class of each working-pixel point from the predicted camera (nearest projected marking within the gate)."""
        c = self.config
        w, h = size
        camera = predicted.camera.rescaled(w, h)
        canvas = np.zeros((h, w), dtype=np.uint8)
        for j, name in enumerate(LINE_CLASSES):
            if not self.pitch.is_on_ground(name):
                continue  # goal frames stand above the grass mask: not named by this detector
            uv, front = camera.project(self.curves.samples_w[name])
            runs = _finite_runs(uv, front, w, h)
            for run in runs:
                cv2.polylines(canvas, [np.round(run).astype(np.int32)], False, j + 1, 1)
        if not canvas.any() or not len(points_px):
            return {}
        src = np.where(canvas > 0, 0, 255).astype(np.uint8)
        dist, labels = cv2.distanceTransformWithLabels(src, cv2.DIST_L2, 5, labelType=cv2.DIST_LABEL_PIXEL)
        lut = np.zeros(labels.max() + 1, dtype=np.uint8)
        on = canvas > 0
        lut[labels[on]] = canvas[on]
        col = np.clip(np.round(points_px[:, 0]).astype(int), 0, w - 1)
        row = np.clip(np.round(points_px[:, 1]).astype(int), 0, h - 1)
        gate = (c.gate_px + c.gate_sigmas * predicted.uncertainty_px) * scale
        cls = lut[labels[row, col]]
        ok = (dist[row, col] <= gate) & (cls > 0)
        out = {}
        d = dist[row, col]
        for j in np.unique(cls[ok]):
            members = ok & (cls == j)
            # The prediction error shifts a whole marking about equally: drop points whose distance
            # to the predicted marking is far from the class's typical one (other markings, clutter).
            dj = d[members]
            median = np.median(dj)
            spread = max(c.class_consistency_px * scale, 2.5 * 1.4826 * np.median(np.abs(dj - median)))
            keep = np.flatnonzero(members)[np.abs(dj - median) <= spread]
            if len(keep) >= c.min_points_per_class:
                # Mean shift along the marking averages the sub-pixel jitter of neighbouring centre points.
                out[LINE_CLASSES[j - 1]] = mean_shift_thin(points_px[keep], c.smoothing_px, c.point_spacing_px,
                                                           iterations=1)
        return out

    # ----------------------------------------------------------------- detect

    def detect(self, image_bgr: np.ndarray, predicted: PredictedCamera | None = None) -> Detections:
        """Detect field markings in one (H, W, 3) uint8 BGR frame (see module docstring)."""
        started = time.perf_counter()
        image = check_image(image_bgr)
        H, W = image.shape[:2]
        work_w = min(self.config.work_width_px, W)
        work_h = max(1, int(round(H * work_w / W)))
        scale = work_w / W
        small = image if work_w == W else cv2.resize(image, (work_w, work_h), interpolation=cv2.INTER_AREA)
        grass, field = self.field_and_grass(small)
        boxes, player_mask = self.players(grass, field)
        # Markings lie on grass: keep only field pixels with grass close by (drops boards, stands).
        k = 2 * self.config.grass_reach_px + 1
        near_grass = cv2.dilate(grass, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (k, k)))
        field = cv2.bitwise_and(field, near_grass)
        allowed = cv2.bitwise_and(field, cv2.bitwise_not(player_mask))
        points, candidates = self.ridges(small, allowed)
        lines = self.name_points(points, predicted, scale, (work_w, work_h)) if predicted is not None else {}
        # The marking map: the accepted centre-line points, one pixel wide at the working size.
        marks = np.zeros((work_h, work_w), dtype=np.uint8)
        if len(points):
            marks[np.clip(np.round(points[:, 1]).astype(int), 0, work_h - 1),
                  np.clip(np.round(points[:, 0]).astype(int), 0, work_w - 1)] = 1

        def to_full(p):
            return (np.asarray(p, float) + 0.5) / scale - 0.5

        detections = Detections(
            width_px=W, height_px=H,
            lines_px={name: to_full(p) for name, p in lines.items()},
            marking_points_px=to_full(_grid_thin(points, self.config.point_spacing_px)),
            marking_mask=marks > 0,
            player_boxes_px=(boxes / scale) if len(boxes) else boxes,
            player_mask=player_mask > 0, field_mask=field > 0,
            info={"detect_ms": 1000 * (time.perf_counter() - started), "work_scale": scale},
        )
        return detections


def _grid_thin(points: np.ndarray, spacing: float) -> np.ndarray:
    """One point per cell of ``spacing`` pixels (the first in input order)."""
    if len(points) == 0:
        return np.zeros((0, 2))
    cells = np.floor(points / spacing).astype(np.int64)
    _, first = np.unique(cells[:, 0] * 1_000_003 + cells[:, 1], return_index=True)
    return points[np.sort(first)]


def _finite_runs(uv: np.ndarray, front: np.ndarray, width: int, height: int, margin: float = 2.0):
    """Pieces of a projected polyline that are in front of the camera and not absurdly far off-image."""
    limit = margin * max(width, height)
    ok = front & np.all(np.isfinite(uv), axis=1)
    with np.errstate(invalid="ignore"):
        ok &= (uv[:, 0] > -limit) & (uv[:, 0] < width + limit) & (uv[:, 1] > -limit) & (uv[:, 1] < height + limit)
    runs, start = [], None
    for i, flag in enumerate(np.append(ok, False)):
        if flag and start is None:
            start = i
        elif not flag and start is not None:
            if i - start >= 2:
                runs.append(uv[start:i])
            start = None
    return runs


def template_mask(camera: Camera, curves: TemplateCurves, width_px: int, height_px: int, thickness_px: int = 1,
                  classes=LINE_CLASSES) -> np.ndarray:
    """(H, W) bool: the projected template drawn as lines of the given thickness."""
    canvas = np.zeros((height_px, width_px), dtype=np.uint8)
    cam = camera if (camera.width_px, camera.height_px) == (width_px, height_px) else camera.rescaled(width_px, height_px)
    for name in classes:
        uv, front = cam.project(curves.samples_w[name])
        for run in _finite_runs(uv, front, width_px, height_px):
            cv2.polylines(canvas, [np.round(run).astype(np.int32)], False, 255, max(1, int(thickness_px)))
    return canvas > 0
