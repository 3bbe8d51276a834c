"""Weight-free re-initialisation: a camera from the unlabelled marking map alone.

:func:`reinit_from_mask` builds camera hypotheses from the structure of the map at each
candidate tripod position (two straight markings put on two pitch lines; a pitch circle
put on an ellipse of the map; scale-free, so tight zooms are found as well as wide views),
scores each against the map and the marking points, and fits the best few after naming
the map's points by the projected template (:func:`label_points_by_camera`). The older
coarse pan/tilt/f grid (:func:`mask_search`) is kept, off by default.

Conventions: world z down, pan 0 looks towards -y (DESIGN.md). No I/O.
"""

from __future__ import annotations

import functools
import itertools
import logging
import math
from dataclasses import dataclass, replace

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.template import TemplateCurves, closest_on_polyline
from broadtrack_graph.reinit.linefit import LineFitConfig, fit_camera_to_lines
from broadtrack_graph.geometry.pitch import Arc, PitchTemplate, Segment
from broadtrack_graph.reinit.lines import (
    DEFAULT_TRIPOD_POSITIONS_W, LabelledScore, ReinitResult, facing_pan_rad,
)

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class RefineSchedule:
    """Label-and-fit rounds of :func:`reinit_from_mask` (sizes as shares of the frame width).

    Each round names the marking points by the nearest projected class within its gate and
    fits :func:`fit_camera_to_lines` with Cauchy scale ``clip(cauchy_per_gate * gate,
    cauchy_min_per_width, cauchy_max_per_width)``.
    """

    gates_per_width: tuple[float, ...]  # labelling gate of each round
    iterations: int  # LM iterations per round
    cauchy_per_gate: float = 0.0
    cauchy_min_per_width: float = 1.0 / 960  # 1 px at 960, 2 px at 1920
    cauchy_max_per_width: float = 1.0 / 960
    k1_free_from_round: int = 2  # k1 is held at 0 before this round (and free in the last round)


TIGHT_SCHEDULE = RefineSchedule((0.02, 0.008, 0.004), 20)
"""Small robust scale throughout: stays in the basin of a close hypothesis, ignores clutter near markings."""

WIDE_SCHEDULE = RefineSchedule((0.025, 0.015, 0.01, 0.006, 0.004), 10, cauchy_per_gate=1.0 / 3.5,
                               cauchy_max_per_width=0.003)
"""A robust scale that starts wide: pulls in a hypothesis 10-20 px off (e.g. a tripod guess several metres off)."""


@dataclass(frozen=True)
class MaskSearchConfig:
    """Settings of :func:`reinit_from_mask` and :func:`mask_search`.

    Pixel sizes are at the working width named in each group (``line_work_width_px`` for the
    map's lines and ellipses, ``score_work_width_px`` for the scores, ``work_width_px`` for the
    grid), so they do not change with the frame size; ``*_per_width`` are shares of the frame width.
    """

    # Straight markings of the map (marking_lines) and the cameras putting two of them on two pitch lines.
    line_work_width_px: int = 960  # the map is reduced to at most this width to find lines and ellipses
    max_lines: int = 12  # at most this many straight markings, strongest first
    line_min_support_px: float = 30.0  # a straight marking has at least this many map pixels
    line_band_px: float = 1.5  # map pixels this close to a line belong to it
    line_max_gap_px: float = 6.0  # a line's pixels split into runs at gaps longer than this ...
    line_min_run_px: float = 10.0  # ... and runs with fewer pixels are specks, not part of it
    line_focal_count: int = 80  # focal lengths tried per pair (geometric over line_focal_range_per_width)
    line_focal_range_per_width: tuple[float, float] = (0.5, 12.0)  # f / W: about 90 to 5 deg of field of view
    line_angle_tol_deg: float = 2.0  # angle between the two viewing planes vs the pitch lines' planes
    line_roll_tol_deg: float = 3.0  # |roll| of the aligned camera (the operator keeps roll about 0)
    line_margin_m: float = 3.0  # a marking's ends must fall on the painted line, within this margin
    tilt_range_deg: tuple[float, float] = (40.0, 95.0)  # accepted tilts of line-pair and circle cameras
    # Ellipses of the map (marking_ellipses) and the cameras putting a pitch circle on them (ellipse_cameras).
    max_ellipses: int = 2  # 0: no circle hypotheses
    ellipse_max_pieces: int = 20  # the largest connected map pieces, fitted in pairs ...
    ellipse_min_piece_px: float = 12.0  # ... of at least this many pixels
    ellipse_check_pixels: int = 1200  # support is counted on at most about this many map pixels
    ellipse_band_px: float = 1.5  # map pixels this close to an ellipse support it ...
    ellipse_min_support_px: float = 80.0  # ... and an ellipse needs this many
    ellipse_max_ratio: float = 0.8  # minor / major axis at most (a ground circle seen from a broadcast camera)
    ellipse_max_tilt_deg: float = 30.0  # major axis within this of the image horizontal (roll about 0)
    ellipse_focal_factors: tuple[float, ...] = tuple(np.geomspace(0.85, 1.3, 13))  # f tried around the estimate
    ellipse_fit_top_k: int = 4  # the closest rough circle cameras fitted to their ellipse's points ...
    ellipse_fit_points: int = 120  # ... (at most this many)
    # Scores of the hypotheses: -F_beta of precision and recall (_MapScorer), at score_work_width_px.
    score_work_width_px: int = 640
    score_cap_px: float = 12.0  # distance transform cap
    score_template_step_m: float = 1.0  # template sampling
    score_hit_px: float = 2.0  # a template sample this close to a marking pixel is found (recall) ...
    score_point_px: float = 3.0  # ... a marking point this close to the projected template is explained (precision)
    score_min_template_px: float = 100.0  # recall denominator floor (working pixels of template)
    score_max_points: int = 200  # marking points used for the precision (evenly subsampled)
    score_beta: float = 1.0
    coarse_hit_px: float = 3.0  # tolerances of the first scoring of all line-pair cameras ...
    coarse_point_px: float = 5.0
    coarse_thin: int = 2  # ... on every second template sample and marking point
    polish_top_k: int = 24  # the best distinct line-pair cameras per focal point are moved along f ...
    polish_focal_steps: int = 9  # ... over one step of the focal grid either side
    distinct_per_width: float = 0.02  # hypotheses closer than this in the image count as one
    other_position_factor: float = 0.95  # scores at focal points other than the first candidate count this much
    poor_score: float = 0.35  # when no hypothesis at the default tripods scores this well, these are tried too:
    far_positions_w: tuple[tuple[float, float, float], ...] = ((0.0, 75.0, -16.5), (0.0, 100.0, -22.0))
    # Refinement: name the marking points by the nearest projected class, fit, shrink the gate (RefineSchedule).
    refine_top_k: int = 6  # at most this many distinct hypotheses are refined (best score first) ...
    refine_cost_share: float = 0.88  # ... after the first, only those scoring this share of its score ...
    max_fits: int = 5  # ... with at most this many label-and-fit runs in all ...
    accept_fit_score: float = 0.6  # ... stopping once a fit scores this (fit score below)
    switch_margin: float = 0.1  # a later hypothesis replaces the best-scoring one when its fit scores this higher
    fit_template_step_m: float = 0.5  # the fit score: the score with a denser template, more points
    fit_max_points: int = 1000  # and tolerances of about 2 and 3 px at 1920
    fit_hit_px: float = 0.7
    fit_point_px: float = 1.0
    schedule: RefineSchedule = TIGHT_SCHEDULE  # the fit of every refined hypothesis
    wide_schedule: RefineSchedule | None = WIDE_SCHEDULE  # also run (the better fit score kept) on hypotheses
    wide_below_score: float = 0.5  # scoring below this (the tripod guess may be metres off); None: never
    position_sigma_m: float = 3.0  # prior on the focal point around the hypothesis's
    min_classes_free_position: int = 3  # with fewer named classes the fit holds the focal point and k1
    sigma_k1: float = 0.05  # prior on k1 around 0 (few far markings leave k1 and f entangled)
    max_fit_points: int = 400  # marking points used by the label-and-fit rounds (evenly subsampled)
    # Optional coarse pan/tilt/f grid (mask_search), scored against the capped distance transform.
    grid_top_k: int = 0  # distinct grid cells kept per candidate position (0: no grid)
    work_width_px: int = 320  # the distance transform of the grid is computed at this width
    cap_px: float = 8.0  # distances are capped here (working pixels)
    hit_px: float = 1.5  # a template sample this close to a marking pixel counts as explained (working pixels)
    miss_px: float = 4.0  # ... this far as contradicted
    miss_weight: float = 1.0  # cost = -(explained length - miss_weight * contradicted length)
    template_step_m: float = 3.0  # template sampling for the grid
    pan_half_range_deg: float = 70.0
    pan_step_deg: float = 2.0
    tilt_min_deg: float = 55.0
    tilt_max_deg: float = 88.0
    tilt_step_deg: float = 1.5
    focal_min_per_width: float = 0.6
    focal_max_per_width: float = 6.0
    focal_count: int = 14


def _distance_map(marking_mask: np.ndarray, work_width_px: int, cap_px: float, frame_width_px: int):
    """Capped distance transform of the marking map at the working width, and working / frame pixel scale."""
    H, W = marking_mask.shape
    w = min(work_width_px, W)
    h = max(1, int(round(H * w / W)))
    small = cv2.resize(marking_mask.astype(np.uint8) * 255, (w, h), interpolation=cv2.INTER_AREA) > 0
    dt = cv2.distanceTransform((~small).astype(np.uint8), cv2.DIST_L2, 3)
    return np.minimum(dt, cap_px).astype(np.float32), w / frame_width_px


def _mask_costs(dt, scale, rel, pans, tilts, focals, config: MaskSearchConfig):
    """Cost (F, P, T) of every (f, pan, tilt) with roll 0: -(explained - w * contradicted template length) / size.

    Template samples within hit_px of a marking pixel count as explained, beyond miss_px as
    contradicted, each weighted by the image length (working pixels) it stands for.
    """
    h, w = dt.shape
    cp, sp = np.cos(pans)[:, None], np.sin(pans)[:, None]
    x1 = cp * rel[:, 0] + sp * rel[:, 1]  # Rz(pan)^T (X - C), (P, N)
    y1 = -sp * rel[:, 0] + cp * rel[:, 1]
    z1 = np.broadcast_to(rel[:, 2], x1.shape)
    ct, st = np.cos(tilts)[None, :, None], np.sin(tilts)[None, :, None]
    xc = np.broadcast_to(x1[:, None, :], (len(pans), len(tilts), len(rel)))
    yc = ct * y1[:, None, :] + st * z1[:, None, :]  # Rx(tilt)^T
    zc = -st * y1[:, None, :] + ct * z1[:, None, :]
    front = zc > 1e-3
    zsafe = np.where(front, zc, 1.0)
    xn = np.where(front, xc / zsafe, 1e9).astype(np.float32)
    yn = np.where(front, yc / zsafe, 1e9).astype(np.float32)
    inv_depth = np.where(front, 1.0 / zsafe, 0.0).astype(np.float32)
    costs = np.full((len(focals), len(pans), len(tilts)), np.inf)
    for i, f in enumerate(focals):
        u = (f * scale) * xn + w / 2.0
        v = (f * scale) * yn + h / 2.0
        inside = (u >= 0) & (u < w - 1) & (v >= 0) & (v < h - 1)
        d = dt[np.where(inside, v, 0).astype(np.int32), np.where(inside, u, 0).astype(np.int32)]
        # Each sample stands for the image length of template it represents (pixels).
        length = np.where(inside, (f * scale * config.template_step_m) * inv_depth, 0.0)
        hit = np.sum(length * (d <= config.hit_px), axis=2)
        miss = np.sum(length * (d >= config.miss_px), axis=2)
        cost = -(hit - config.miss_weight * miss) / (w + h)
        cost[inside.sum(axis=2) < 8] = np.inf
        costs[i] = cost
    return costs


@functools.lru_cache(maxsize=4)
def _ground_template_map(dimensions, resolution_m: float = 0.1):
    """Nearest painted ground marking of every cell of a grid over the pitch (and 8 m around it).

    Returns:
        nearest_xy_w: (h, w, 2) float32 metres, the nearest marking point of each cell;
        origin_w: (2,) metres of cell (0, 0); resolution_m.
    """
    pitch = PitchTemplate(dimensions)
    half_l, half_w = dimensions.length_m / 2 + 8.0, dimensions.width_m / 2 + 8.0
    w, h = int(round(2 * half_l / resolution_m)) + 1, int(round(2 * half_w / resolution_m)) + 1
    origin = np.array([-half_l, -half_w])
    image = np.ones((h, w), np.uint8)
    for name, points in pitch.sample_uniform(resolution_m / 2).items():
        if pitch.is_on_ground(name):
            cells = np.rint((points[:, :2] - origin) / resolution_m).astype(int)
            image[cells[:, 1], cells[:, 0]] = 0
    _, labels = cv2.distanceTransformWithLabels(image, cv2.DIST_L2, 5, labelType=cv2.DIST_LABEL_PIXEL)
    rows, cols = np.nonzero(image == 0)  # labels number the zero cells in row-major order from 1
    zero_xy = (np.column_stack([cols, rows]) * resolution_m + origin).astype(np.float32)
    return zero_xy[labels - 1], origin, resolution_m


class _MapScorer:
    """Scores roll-0 cameras against one marking map: cost = -F_beta(precision, recall) (lower is better).

    recall: template length (working pixels, samples ``score_template_step_m`` apart) within
    ``hit_px`` of a marking pixel, over the template length in the image (at least
    ``score_min_template_px``); precision: share of the marking points whose ray meets the pitch
    near a painted marking that projects back within ``point_px`` of the point. Pixel sizes at
    ``score_work_width_px``; beta is ``score_beta``.
    """

    def __init__(self, marking_mask: np.ndarray, marking_points_px: np.ndarray, frame_size, pitch: PitchTemplate,
                 config: MaskSearchConfig):
        self.W, self.H = frame_size
        self.config = config
        self.dt, self.scale = _distance_map(marking_mask, config.score_work_width_px, config.score_cap_px, self.W)
        ground = [n for n in pitch.elements if pitch.is_on_ground(n)]
        self.samples_w = np.vstack(list(pitch.sample_uniform(config.score_template_step_m, classes=ground).values()))
        points = np.asarray(marking_points_px, float).reshape(-1, 2)
        if len(points) > config.score_max_points:
            points = points[np.linspace(0, len(points) - 1, config.score_max_points).astype(int)]
        self.points_c = points - [self.W / 2.0, self.H / 2.0]
        self.nearest_xy, self.origin, self.resolution = _ground_template_map(pitch.dimensions)

    def camera_cost(self, camera: Camera, hit_px: float, point_px: float) -> float:
        """The cost of one full camera (any roll, k1, focal point) at the frame size."""
        config, dt, scale = self.config, self.dt, self.scale
        h, w = dt.shape
        points_c = camera.world_to_camera(self.samples_w)
        uv, front = camera.project(self.samples_w)
        uv = uv * scale
        inside = front & np.all(np.isfinite(uv), axis=1)
        inside &= (uv[:, 0] >= 0) & (uv[:, 0] < w - 1) & (uv[:, 1] >= 0) & (uv[:, 1] < h - 1)
        if inside.sum() < 8:
            return math.inf
        d = dt[uv[inside, 1].astype(np.int32), uv[inside, 0].astype(np.int32)]
        length = camera.focal_px * scale * config.score_template_step_m / points_c[inside, 2]
        recall = float(np.sum(length * (d <= hit_px)) / max(np.sum(length), config.score_min_template_px))
        precision = 1.0
        if len(self.points_c):
            points_px = self.points_c + [self.W / 2.0, self.H / 2.0]
            on_pitch, hits = camera.ground_intersection(points_px)
            col = np.rint((on_pitch[:, 0] - self.origin[0]) / self.resolution)
            row = np.rint((on_pitch[:, 1] - self.origin[1]) / self.resolution)
            ok = hits & (col >= 0) & (col < self.nearest_xy.shape[1]) & (row >= 0) & (row < self.nearest_xy.shape[0])
            near = np.zeros((len(points_px), 3))
            near[ok, :2] = self.nearest_xy[row[ok].astype(int), col[ok].astype(int)]
            back, front_back = camera.project(near)
            ok &= front_back
            dist = np.linalg.norm(np.where(ok[:, None], back - points_px, np.inf), axis=1)
            precision = float(np.mean(ok & (dist < point_px / scale)))
        b2 = config.score_beta ** 2
        score = (1 + b2) * precision * recall / (b2 * precision + recall) if precision + recall > 0 else 0.0
        return -score

    def costs(self, position_w, pans, tilts, focals, hit_px: float, point_px: float, chunk: int = 128,
              thin: int = 1) -> np.ndarray:
        """(K,) costs of the cameras (pans, tilts: radians, focals: frame pixels; roll 0) at the focal point position_w.

        thin: use every thin-th template sample and marking point (a quicker, coarser score).
        inf when fewer than 8 template samples land in the image.
        """
        dt, scale, config = self.dt, self.scale, self.config
        h, w = dt.shape
        C = np.asarray(position_w, float)
        rel = self.samples_w[::thin] - C
        step_m = config.score_template_step_m * thin
        pts = self.points_c[::thin]
        tol2 = (point_px / scale) ** 2
        b2 = config.score_beta ** 2
        pans, tilts, focals = (np.asarray(v, float).ravel() for v in (pans, tilts, focals))
        out = np.full(len(pans), np.inf)
        for s in range(0, len(pans), chunk):
            p, t, f = pans[s:s + chunk, None], tilts[s:s + chunk, None], focals[s:s + chunk, None]
            cp, sp, ct, st = np.cos(p), np.sin(p), np.cos(t), np.sin(t)
            # Template samples into the camera: Rx(tilt)^T Rz(pan)^T (X - C).
            x1 = cp * rel[:, 0] + sp * rel[:, 1]
            y1 = -sp * rel[:, 0] + cp * rel[:, 1]
            yc = ct * y1 + st * rel[:, 2]
            zc = -st * y1 + ct * rel[:, 2]
            front = zc > 1e-3
            inv = np.where(front, 1.0 / np.where(front, zc, 1.0), 0.0)
            u = (f * scale) * x1 * inv + w / 2.0
            v = (f * scale) * yc * inv + h / 2.0
            inside = front & (u >= 0) & (u < w - 1) & (v >= 0) & (v < h - 1)
            d = dt[np.where(inside, v, 0).astype(np.int32), np.where(inside, u, 0).astype(np.int32)]
            length = np.where(inside, (f * scale) * step_m * inv, 0.0)
            recall = np.sum(length * (d <= hit_px), axis=1) / np.maximum(np.sum(length, axis=1),
                                                                         config.score_min_template_px)
            if len(pts):
                # Marking points out to the pitch (rays Rz(pan) Rx(tilt) (u, v, f)), to their nearest painted
                # marking, and back into the image.
                y_r = ct * pts[:, 1] - st * f
                z_w = st * pts[:, 1] + ct * f
                x_w = cp * pts[:, 0] - sp * y_r
                y_w = sp * pts[:, 0] + cp * y_r
                down = z_w > 1e-9
                reach = np.where(down, -C[2] / np.where(down, z_w, 1.0), 0.0)
                col = np.rint((C[0] + reach * x_w - self.origin[0]) / self.resolution).astype(np.int64)
                row = np.rint((C[1] + reach * y_w - self.origin[1]) / self.resolution).astype(np.int64)
                on_grid = down & (col >= 0) & (col < self.nearest_xy.shape[1]) & (row >= 0) & (row < self.nearest_xy.shape[0])
                near = self.nearest_xy[np.where(on_grid, row, 0), np.where(on_grid, col, 0)]
                rx, ry = near[..., 0] - C[0], near[..., 1] - C[1]
                x1 = cp * rx + sp * ry
                y1 = -sp * rx + cp * ry
                yc = ct * y1 - st * C[2]
                zc = -st * y1 - ct * C[2]
                ok = on_grid & (zc > 1e-3)
                zc = np.where(ok, zc, 1.0)
                du = f * x1 / zc - pts[:, 0]
                dv = f * yc / zc - pts[:, 1]
                precision = np.mean(ok & (du * du + dv * dv < tol2), axis=1)
            else:
                precision = np.ones_like(recall)
            with np.errstate(invalid="ignore", divide="ignore"):
                score = np.where(precision + recall > 0, (1 + b2) * precision * recall / (b2 * precision + recall), 0.0)
            cost = -score
            cost[inside.sum(axis=1) < max(4, 8 // thin)] = np.inf
            out[s:s + chunk] = cost
        return out


def _best_cells(costs, count, spacing=(2, 3, 3)):
    order = np.argsort(costs, axis=None)
    used = []
    for flat in order[:5000]:
        cell = np.unravel_index(flat, costs.shape)
        if not np.isfinite(costs[cell]):
            break
        if any(all(abs(a - b) <= s for a, b, s in zip(cell, other, spacing)) for other in used):
            continue
        used.append(cell)
        if len(used) >= count:
            break
    return used


def mask_search(marking_mask: np.ndarray, position_w, camera_size: tuple[int, int], pitch: PitchTemplate,
                config: MaskSearchConfig = MaskSearchConfig(), samples_w: np.ndarray | None = None):
    """Global pan/tilt/f grid search at a fixed focal point against the distance transform of the marking map.

    A coarse grid at ``work_width_px`` proposes the best distinct cells; each is refined on a
    fine local grid at twice that width. Cost: template length (pixels) landing on markings
    minus the length landing far from any (:func:`_mask_costs`).

    Returns:
        list of (cost, Camera at camera_size, roll 0, k1 0), best first.
    """
    W, H = camera_size
    if samples_w is None:
        samples = pitch.sample_uniform(config.template_step_m, classes=[n for n in pitch.elements if pitch.is_on_ground(n)])
        samples_w = np.vstack(list(samples.values()))
    C = np.asarray(position_w, float)
    rel = samples_w - C
    dt, scale = _distance_map(marking_mask, config.work_width_px, config.cap_px, W)
    pans = facing_pan_rad(C) + np.radians(np.arange(-config.pan_half_range_deg, config.pan_half_range_deg + 1e-9,
                                                      config.pan_step_deg))
    tilts = np.radians(np.arange(config.tilt_min_deg, config.tilt_max_deg + 1e-9, config.tilt_step_deg))
    focals = W * np.geomspace(config.focal_min_per_width, config.focal_max_per_width, config.focal_count)
    costs = _mask_costs(dt, scale, rel, pans, tilts, focals, config)
    fine_dt, fine_scale = _distance_map(marking_mask, 2 * config.work_width_px, 2 * config.cap_px, W)
    fine_config = replace(config, hit_px=2 * config.hit_px, miss_px=2 * config.miss_px)
    ratio = (config.focal_max_per_width / config.focal_min_per_width) ** (1 / max(config.focal_count - 1, 1))
    picked = []
    for i, p, t in _best_cells(costs, config.grid_top_k or 3):
        fine_pans = pans[p] + np.radians(np.linspace(-config.pan_step_deg, config.pan_step_deg, 9))
        fine_tilts = tilts[t] + np.radians(np.linspace(-config.tilt_step_deg, config.tilt_step_deg, 9))
        fine_focals = focals[i] * np.geomspace(1 / ratio, ratio, 9)
        fine = _mask_costs(fine_dt, fine_scale, rel, fine_pans, fine_tilts, fine_focals, fine_config)
        a, b, c = np.unravel_index(np.argmin(fine), fine.shape)
        picked.append((float(fine[a, b, c]), Camera(fine_focals[a], 0.0, fine_pans[b], fine_tilts[c], 0.0, C, W, H)))
    picked.sort(key=lambda item: item[0])
    return picked


# ----------------------------------------------------------------- straight markings and line-pair cameras


@dataclass(frozen=True)
class ImageLine:
    """A straight marking found in the marking map, in frame pixels.

    normal: (2,) unit normal n; points p on the line satisfy n . p + offset_px = 0.
    centre_px: (2,) middle of its support; direction: (2,) unit, along the line.
    extent_px: (lo, hi) 10th and 90th percentiles of its support along ``direction`` from ``centre_px``.
    support_px: number of map pixels on it, in frame pixels (about its visible length).
    """

    normal: np.ndarray
    offset_px: float
    centre_px: np.ndarray
    direction: np.ndarray
    extent_px: tuple[float, float]
    support_px: float


def _at_most_width(marking_mask: np.ndarray, width_px: int) -> np.ndarray:
    """The bool map reduced (area-averaged, any marked pixel kept) to at most width_px wide."""
    h, w = marking_mask.shape
    if w <= width_px:
        return marking_mask
    h_new = max(1, int(round(h * width_px / w)))
    return cv2.resize(marking_mask.astype(np.uint8) * 255, (width_px, h_new), interpolation=cv2.INTER_AREA) > 0


def marking_lines(marking_mask: np.ndarray, frame_width_px: int, config: MaskSearchConfig = MaskSearchConfig()
                  ) -> list[ImageLine]:
    """Straight markings of the map by a greedy Hough transform: take the strongest line, remove its pixels, repeat.

    Removing each line's pixels before looking for the next keeps one long marking from
    returning as many near-copies and lets short dashed lines through after long ones.

    Args:
        marking_mask: (h, w) bool map (any size of the frame's aspect ratio).
        frame_width_px: the frame width the lines are returned in.

    Returns:
        Up to ``max_lines`` lines, strongest first.
    """
    marking_mask = _at_most_width(marking_mask, config.line_work_width_px)
    h, w = marking_mask.shape
    unit = w / 960.0
    min_support = max(10.0, config.line_min_support_px * unit)
    ys, xs = np.nonzero(marking_mask)
    if len(xs) < min_support:
        return []
    pix = np.column_stack([xs, ys]).astype(np.float32) - np.float32([w / 2.0, h / 2.0])
    theta_bins = 180
    thetas = np.arange(theta_bins) * (math.pi / theta_bins)
    cs, sn = np.cos(thetas).astype(np.float32), np.sin(thetas).astype(np.float32)
    r_max = int(math.ceil(math.hypot(w, h) / 2)) + 2
    n_r = 2 * r_max + 1
    offsets = (n_r * np.arange(theta_bins)).astype(np.int64)

    def votes(points):
        r = np.rint(points[:, :1] * cs + points[:, 1:] * sn).astype(np.int64) + r_max
        acc = np.bincount((r + offsets).ravel(), minlength=n_r * theta_bins).astype(np.int32)
        smooth = acc.copy()  # a 3-bin window across rho: lines a pixel off the bin centre still collect all votes
        smooth[1:] += acc[:-1]
        smooth[:-1] += acc[1:]
        return smooth

    acc = votes(pix)
    alive = np.ones(len(pix), bool)
    band = config.line_band_px * unit
    scale = frame_width_px / w
    lines: list[ImageLine] = []
    for _ in range(3 * config.max_lines):
        k = int(np.argmax(acc))
        if acc[k] < min_support:
            break
        t_i, r_i = divmod(k, n_r)
        normal = np.array([cs[t_i], sn[t_i]], float)
        near = alive & (np.abs(pix @ normal - (r_i - r_max)) < 2.0 * unit)
        centre = pix[near].mean(axis=0) if near.any() else normal * (r_i - r_max)
        for _refit in range(2):  # total least squares on the band, twice
            sel = pix[near]
            if len(sel) < 5:
                break
            centre = sel.mean(axis=0)
            _, _, vt = np.linalg.svd(sel - centre, full_matrices=False)
            normal = vt[1]
            near = near | (alive & (np.abs((pix - centre) @ normal) < band))
        acc -= votes(pix[near])
        alive &= ~near
        direction = np.array([-normal[1], normal[0]])
        # Pieces of the line: runs of pixels along it without gaps; specks (short runs) do not count.
        along = np.sort((pix[near] - centre) @ direction)
        breaks = np.nonzero(np.diff(along) > config.line_max_gap_px * unit)[0] + 1
        runs = [run for run in np.split(along, breaks) if len(run) >= config.line_min_run_px * unit]
        support = sum(len(run) for run in runs)
        if support < min_support:
            continue
        lo, hi = np.percentile(np.concatenate(runs), [10.0, 90.0])  # stray runs at the ends do not count
        centre_px = (centre + [w / 2.0, h / 2.0]) * scale
        lines.append(ImageLine(normal, float(-normal @ centre_px), centre_px, direction,
                               (float(lo * scale), float(hi * scale)), float(support * scale)))
        if len(lines) >= config.max_lines:
            break
    return lines


def pitch_lines(pitch: PitchTemplate):
    """The straight ground markings as infinite lines with their painted extents.

    Returns:
        points_w: (L, 3) a point of each line (metres); directions_w: (L, 3) unit (x or y axis);
        extents: list of L lists of (lo, hi) painted intervals along the direction (metres).
    """
    found: dict[tuple, list] = {}
    for name, element in pitch.elements.items():
        if not isinstance(element, Segment) or not pitch.is_on_ground(name):
            continue
        a, b = np.asarray(element.start_w), np.asarray(element.end_w)
        if abs(a[0] - b[0]) < 1e-9:
            found.setdefault((0, round(a[0], 4)), []).append(tuple(sorted((a[1], b[1]))))
        else:
            found.setdefault((1, round(a[1], 4)), []).append(tuple(sorted((a[0], b[0]))))
    points, directions, extents = [], [], []
    for (axis, value), spans in sorted(found.items()):
        points.append([value, 0.0, 0.0] if axis == 0 else [0.0, value, 0.0])
        directions.append([0.0, 1.0, 0.0] if axis == 0 else [1.0, 0.0, 0.0])
        extents.append(spans)
    return np.asarray(points), np.asarray(directions), extents


def _symmetric_triads(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """(K, 3, 3) orthonormal frames (columns) built from the bisector and difference of unit vectors a, b (K, 3)."""
    e1 = a + b
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = a - b
    e2 /= np.linalg.norm(e2, axis=1, keepdims=True)
    return np.stack([e1, e2, np.cross(e1, e2)], axis=2)


@dataclass
class LinePairs:
    """Line-pair camera hypotheses at one focal point, re-solvable at another focal length.

    line_a, line_b: (K,) indices of the two image lines; world_a, world_b: (K,) indices of the
    pitch lines they are put on (:func:`pitch_lines`); sign: (K,) 0..3, the signs of the two
    image-line plane normals (``_PairGeometry.align``); focals_px, pans_rad, tilts_rad, rolls_rad: (K,) the cameras.
    """

    line_a: np.ndarray
    line_b: np.ndarray
    world_a: np.ndarray
    world_b: np.ndarray
    sign: np.ndarray
    focals_px: np.ndarray
    pans_rad: np.ndarray
    tilts_rad: np.ndarray
    rolls_rad: np.ndarray

    def subset(self, keep) -> "LinePairs":
        return LinePairs(*(getattr(self, name)[keep] for name in self.__dataclass_fields__))


class _PairGeometry:
    """Viewing-plane normals of the image lines (per focal length) and of the pitch lines (at one focal point)."""

    def __init__(self, lines: list[ImageLine], position_w, frame_size, lines_w):
        W, H = frame_size
        self.C = np.asarray(position_w, float)
        self.points_w, self.directions_w, self.extents = lines_w
        most = max(len(e) for e in self.extents)
        self.spans = np.full((len(self.extents), most, 2), np.nan)  # painted intervals, NaN-padded
        for index, extent in enumerate(self.extents):
            self.spans[index, :len(extent)] = extent
        self.normals_img = np.array([line.normal for line in lines]).reshape(-1, 2)
        self.offsets_c = np.array([line.offset_px for line in lines]) + self.normals_img @ [W / 2.0, H / 2.0]
        normals_w = np.cross(self.directions_w, self.points_w - self.C)
        self.normals_w = normals_w / np.linalg.norm(normals_w, axis=1, keepdims=True)
        self.centres_c = np.array([line.centre_px for line in lines]).reshape(-1, 2) - [W / 2.0, H / 2.0]
        self.directions = np.array([line.direction for line in lines]).reshape(-1, 2)
        self.ends = np.array([line.extent_px for line in lines]).reshape(-1, 2)

    def camera_normals(self, index, focals):
        """(K, 3) unit normals of the viewing planes of image lines ``index`` at focal lengths ``focals``."""
        n = np.column_stack([self.normals_img[index], self.offsets_c[index] / focals])
        return n / np.linalg.norm(n, axis=1, keepdims=True)

    def align(self, line_a, line_b, world_a, world_b, signs, focals):
        """Rotations taking the pitch-line plane normals onto the image-line ones (signed as ``signs``).

        signs: (K,) 0..3, bit 0 flips the first image normal, bit 1 the second (a plane normal has no sign).

        Returns:
            pan, tilt, roll (K,) radians, R (K, 3, 3) world to camera, and the mismatch (K,) in
            degrees between the angles of the two normal pairs.
        """
        c1 = self.camera_normals(line_a, focals) * np.where(signs & 1, -1.0, 1.0)[:, None]
        c2 = self.camera_normals(line_b, focals) * np.where(signs & 2, -1.0, 1.0)[:, None]
        w1, w2 = self.normals_w[world_a], self.normals_w[world_b]
        mismatch = np.degrees(np.abs(np.arccos(np.clip(np.sum(c1 * c2, axis=1), -1, 1))
                                     - np.arccos(np.clip(np.sum(w1 * w2, axis=1), -1, 1))))
        R = _symmetric_triads(c1, c2) @ np.transpose(_symmetric_triads(w1, w2), (0, 2, 1))  # R w = c
        tilt = np.arctan2(np.hypot(R[:, 0, 2], R[:, 1, 2]), R[:, 2, 2])
        pan = np.arctan2(R[:, 2, 0], -R[:, 2, 1])
        roll = np.arctan2(R[:, 0, 2], R[:, 1, 2])
        return pan, tilt, roll, R, mismatch

    def ends_on_painted(self, line_index, world_index, R, focals, margin_m: float) -> np.ndarray:
        """(K,) bool: both ends of each image line back-project (camera R, f) onto the painted part of its pitch line."""
        ok = np.ones(len(line_index), bool)
        spans = self.spans[world_index]  # (K, S, 2)
        for end in (0, 1):
            uv = self.centres_c[line_index] + self.ends[line_index, end][:, None] * self.directions[line_index]
            rays_w = np.einsum("kji,kj->ki", R, np.column_stack([uv, focals]))  # R^T (u, v, f)
            with np.errstate(divide="ignore", invalid="ignore"):
                reach = -self.C[2] / rays_w[:, 2]
            ok &= reach > 0
            along = np.sum((self.C + np.where(reach > 0, reach, 0.0)[:, None] * rays_w) * self.directions_w[world_index],
                           axis=1)[:, None]
            ok &= np.any((along > spans[:, :, 0] - margin_m) & (along < spans[:, :, 1] + margin_m), axis=1)
        return ok


def line_pair_cameras(lines: list[ImageLine], position_w, frame_size: tuple[int, int], pitch: PitchTemplate,
                      config: MaskSearchConfig = MaskSearchConfig(), lines_w=None) -> LinePairs:
    """Cameras (roll about 0, focal point at position_w) that put two straight markings on two pitch lines.

    An image line and the focal point span a viewing plane, with normal ``(a, b, c / f)`` in the
    camera frame for the line ``a u + b v + c = 0`` (centred pixels); a pitch line and the focal
    point span a plane with a known world normal. For every focal length of a geometric grid,
    every pair of image lines and every ordered pair of pitch lines whose plane angles agree
    (``line_angle_tol_deg``), the rotation aligning the two normal pairs (symmetric triads, the
    sign choices of the image normals) is kept when its roll is near 0, its tilt plausible, and
    both markings' ends back-project onto the painted part of their pitch line. f is gridded,
    not solved: two lines at right angles in the image leave it ill-conditioned
    (:func:`resolve_line_pairs` moves a hypothesis along f).

    Returns:
        LinePairs (empty when fewer than two lines).
    """
    empty = LinePairs(*(np.zeros(0, int) for _ in range(5)), *(np.zeros(0) for _ in range(4)))
    if len(lines) < 2:
        return empty
    W, _ = frame_size
    geometry = _PairGeometry(lines, position_w, frame_size, lines_w if lines_w is not None else pitch_lines(pitch))
    focals = W * np.geomspace(*config.line_focal_range_per_width, config.line_focal_count)
    L, F, P = len(lines), len(focals), len(geometry.points_w)
    n_c = geometry.camera_normals(np.repeat(np.arange(L), F), np.tile(focals, L)).reshape(L, F, 3)
    nw = geometry.normals_w
    ii, jj = np.triu_indices(L, 1)
    pp, qq = np.nonzero(~np.eye(P, dtype=bool))
    # Signed angles of the normal pairs: image pairs for each sign choice (bit 0 flips the first normal,
    # bit 1 the second; flipping both gives the same angle) and pitch pairs.
    dot_c = np.sum(n_c[ii] * n_c[jj], axis=2)  # (pairs, F)
    angle_c = np.degrees(np.arccos(np.clip(np.stack([dot_c, -dot_c]), -1.0, 1.0)))  # (2, pairs, F): same, opposite
    angle_w = np.degrees(np.arccos(np.clip(np.sum(nw[pp] * nw[qq], axis=1), -1.0, 1.0)))
    order = np.argsort(angle_w)
    sorted_w = angle_w[order]
    # Pitch-line pairs whose plane angle is within the tolerance, found by bisection on the sorted angles.
    lo = np.searchsorted(sorted_w, angle_c.ravel() - config.line_angle_tol_deg)
    hi = np.searchsorted(sorted_w, angle_c.ravel() + config.line_angle_tol_deg)
    counts = hi - lo
    if not counts.sum():
        return empty
    flat = np.repeat(np.arange(len(counts)), counts)
    k_w = order[np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts) + np.repeat(lo, counts)]
    k_rel, rest = np.divmod(flat, len(ii) * F)
    k_pair, k_f = np.divmod(rest, F)
    # With roll about 0 the camera's x axis is horizontal, so an image line's plane normal has an x
    # component no larger than the horizontal part of its pitch line's plane normal.
    slack = math.sin(math.radians(config.line_roll_tol_deg))
    horizontal_w = np.hypot(nw[:, 0], nw[:, 1])
    x_c = np.abs(n_c[:, :, 0])
    keep = ((x_c[ii[k_pair], k_f] <= horizontal_w[pp[k_w]] + slack)
            & (x_c[jj[k_pair], k_f] <= horizontal_w[qq[k_w]] + slack))
    k_rel, k_pair, k_f, k_w = k_rel[keep], k_pair[keep], k_f[keep], k_w[keep]
    # The two overall signs of each relative choice: codes 0 / 3 (same), 1 / 2 (opposite).
    code = np.concatenate([np.where(k_rel == 0, 0, 1), np.where(k_rel == 0, 3, 2)])
    k_pair, k_f, k_w = np.tile(k_pair, 2), np.tile(k_f, 2), np.tile(k_w, 2)
    # Camera-side triads per (sign code, image pair, focal), pitch-side per pitch pair; only the rotation
    # entries needed for pan, tilt and roll are formed for every candidate.
    c1 = n_c[ii][None] * np.array([1.0, -1.0, 1.0, -1.0])[:, None, None, None]
    c2 = n_c[jj][None] * np.array([1.0, 1.0, -1.0, -1.0])[:, None, None, None]
    t_c = _symmetric_triads(c1.reshape(-1, 3), c2.reshape(-1, 3)).reshape(4, len(ii), F, 3, 3)
    t_w = _symmetric_triads(nw[pp], nw[qq])
    # Third column of R = Tc Tw^T: the pitch's vertical seen from the camera gives tilt and roll.
    column = np.einsum("kaj,kj->ka", t_c[code, k_pair, k_f], t_w[k_w, 2, :])
    tilt = np.arctan2(np.hypot(column[:, 0], column[:, 1]), column[:, 2])
    roll = np.arctan2(column[:, 0], column[:, 1])
    tilt_lo, tilt_hi = np.radians(config.tilt_range_deg)
    keep = (np.abs(roll) < math.radians(config.line_roll_tol_deg)) & (tilt > tilt_lo) & (tilt < tilt_hi)
    k_pair, k_f, k_w, code = k_pair[keep], k_f[keep], k_w[keep], code[keep]
    candidates = LinePairs(ii[k_pair], jj[k_pair], pp[k_w], qq[k_w], code, focals[k_f], focals[k_f], focals[k_f],
                           focals[k_f])
    return resolve_line_pairs(geometry, candidates, candidates.focals_px, config)


def resolve_line_pairs(geometry: _PairGeometry, pairs: LinePairs, focals_px: np.ndarray,
                       config: MaskSearchConfig) -> LinePairs:
    """The same line-pair assignments solved at new focal lengths, keeping the plausible cameras (roll, tilt, ends)."""
    return _resolve(geometry, pairs, focals_px, config)[0]


def _resolve(geometry: _PairGeometry, pairs: LinePairs, focals_px: np.ndarray, config: MaskSearchConfig):
    """:func:`resolve_line_pairs` and the (K,) mask of the kept input rows."""
    pan, tilt, roll, R, mismatch = geometry.align(pairs.line_a, pairs.line_b, pairs.world_a, pairs.world_b, pairs.sign,
                                                  focals_px)
    tilt_lo, tilt_hi = np.radians(config.tilt_range_deg)
    keep = ((np.abs(roll) < math.radians(config.line_roll_tol_deg)) & (tilt > tilt_lo) & (tilt < tilt_hi)
            & (mismatch < config.line_angle_tol_deg))
    for line_index, world_index in ((pairs.line_a, pairs.world_a), (pairs.line_b, pairs.world_b)):
        idx = np.nonzero(keep)[0]
        keep[idx] = geometry.ends_on_painted(line_index[idx], world_index[idx], R[idx], focals_px[idx],
                                             config.line_margin_m)
    return LinePairs(pairs.line_a[keep], pairs.line_b[keep], pairs.world_a[keep], pairs.world_b[keep],
                     pairs.sign[keep], focals_px[keep], pan[keep], tilt[keep], roll[keep]), keep


def _best_along_focal(geometry: _PairGeometry, pairs: LinePairs, position_w, scorer: "_MapScorer",
                      config: MaskSearchConfig, steps: np.ndarray):
    """Each pair moved along f (factors ``steps``; both lines stay aligned) to its best-scoring focal length.

    Returns:
        (LinePairs, costs (K,)) of the same length as ``pairs`` (cost inf where no step gave a plausible camera).
    """
    K, S = len(pairs.focals_px), len(steps)
    many = pairs.subset(np.repeat(np.arange(K), S))
    moved, keep = _resolve(geometry, many, many.focals_px * np.tile(steps, K), config)
    costs = np.full(K * S, np.inf)
    costs[keep] = scorer.costs(position_w, moved.pans_rad, moved.tilts_rad, moved.focals_px, config.score_hit_px,
                               config.score_point_px)
    best = np.argmin(costs.reshape(K, S), axis=1) + S * np.arange(K)
    full = LinePairs(*(np.zeros(K * S, getattr(many, name).dtype) for name in LinePairs.__dataclass_fields__))
    for name in LinePairs.__dataclass_fields__:
        getattr(full, name)[keep] = getattr(moved, name)
    return full.subset(best), costs[best]


# ----------------------------------------------------------------- ellipses: the circles of the pitch


@dataclass(frozen=True)
class ImageEllipse:
    """An ellipse found in the marking map (frame pixels): centre_px (2,), semi-axes (a >= b), angle_rad of a
    to the image x axis, and support_px: map pixels on it (in frame pixels)."""

    centre_px: np.ndarray
    semi_axes_px: tuple[float, float]
    angle_rad: float
    support_px: float

    def distances_px(self, points_px: np.ndarray) -> np.ndarray:
        """(N,) approximate distances (first order) of frame-pixel points (N, 2) to the ellipse."""
        c, s = math.cos(self.angle_rad), math.sin(self.angle_rad)
        d = np.asarray(points_px, float) - self.centre_px
        x, y = d[:, 0] * c + d[:, 1] * s, -d[:, 0] * s + d[:, 1] * c
        a, b = self.semi_axes_px
        return np.abs((x / a) ** 2 + (y / b) ** 2 - 1.0) / np.maximum(2.0 * np.hypot(x / a**2, y / b**2), 1e-12)


def marking_ellipses(marking_mask: np.ndarray, frame_width_px: int, config: MaskSearchConfig = MaskSearchConfig()
                     ) -> list[ImageEllipse]:
    """Ellipses through pieces of the marking map: the image of a pitch circle (centre circle, penalty arcs).

    Connected pieces of the map are fitted in pairs (and the long ones alone) with an ellipse;
    an ellipse is kept when it is wide, about level (roll about 0), and many map pixels lie on
    it; the best ``max_ellipses`` distinct ones are returned, most supported first.
    """
    marking_mask = _at_most_width(marking_mask, config.line_work_width_px)
    h, w = marking_mask.shape
    unit = w / 960.0
    count, labels, stats, _ = cv2.connectedComponentsWithStats(marking_mask.astype(np.uint8), connectivity=8)
    areas = stats[1:, cv2.CC_STAT_AREA]
    pieces = [1 + k for k in np.argsort(-areas)[: config.ellipse_max_pieces] if areas[k] >= config.ellipse_min_piece_px * unit]
    if not pieces:
        return []
    ys, xs = np.nonzero(labels > 0)
    pixels = np.column_stack([xs, ys]).astype(np.float32)
    piece_pixels = {}
    for label in pieces:
        own = pixels[labels[ys, xs] == label]
        piece_pixels[label] = own[np.linspace(0, len(own) - 1, min(len(own), 40)).astype(int)]
    every = max(1, len(pixels) // config.ellipse_check_pixels)
    pixels = pixels[::every]  # support is counted on at most about ellipse_check_pixels map pixels
    trials = [(a,) for a in pieces if areas[a - 1] >= 60 * unit] + list(itertools.combinations(pieces, 2))
    tol = config.ellipse_band_px * unit
    found = []
    for trial in trials:
        sample = np.vstack([piece_pixels[label] for label in trial])
        if len(sample) < 6:
            continue
        (cx, cy), (d1, d2), angle_deg = cv2.fitEllipse(sample)
        a, b = max(d1, d2) / 2.0, min(d1, d2) / 2.0
        if not (np.isfinite(a) and b > 1.0 and 0.03 * w < a < 3.0 * w and b / a <= config.ellipse_max_ratio):
            continue
        theta = math.radians(angle_deg) + (0.0 if d1 >= d2 else math.pi / 2)
        if abs(math.sin(theta)) > math.sin(math.radians(config.ellipse_max_tilt_deg)):
            continue
        c, s = math.cos(theta), math.sin(theta)
        x = (pixels[:, 0] - cx) * c + (pixels[:, 1] - cy) * s
        y = -(pixels[:, 0] - cx) * s + (pixels[:, 1] - cy) * c
        F = (x / a) ** 2 + (y / b) ** 2 - 1.0
        grad = 2.0 * np.hypot(x / a**2, y / b**2)
        support = int(np.sum(np.abs(F) < tol * np.maximum(grad, 1e-9))) * every
        found.append((support, np.array([cx, cy]), (a, b), theta))
    found.sort(key=lambda item: -item[0])
    scale = frame_width_px / w
    out: list[ImageEllipse] = []
    for support, centre, (a, b), theta in found:
        if support < config.ellipse_min_support_px * unit:
            break
        if any(np.linalg.norm(centre * scale - e.centre_px) < 0.1 * a * scale for e in out):
            continue
        out.append(ImageEllipse(centre * scale, (a * scale, b * scale), theta, support * scale))
        if len(out) >= config.max_ellipses:
            break
    return out


def _pointing(direction_w: np.ndarray, ray_c: np.ndarray):
    """Pan and tilt (radians) with roll 0 turning the world direction onto the camera ray (both (3,)); [] if none."""
    w = direction_w / np.linalg.norm(direction_w)
    c = ray_c / np.linalg.norm(ray_c)
    h = math.hypot(w[0], w[1])
    if h < 1e-9 or abs(c[0]) > h:
        return []
    phi, spread = math.atan2(w[1], w[0]), math.acos(c[0] / h)
    out = []
    for pan in (phi + spread, phi - spread):
        m_y = -math.sin(pan) * w[0] + math.cos(pan) * w[1]
        tilt = math.atan2(w[2], m_y) - math.atan2(c[2], c[1])
        out.append((pan, math.remainder(tilt, 2 * math.pi)))
    return out


def ellipse_cameras(ellipses: list[ImageEllipse], position_w, frame_size, pitch: PitchTemplate,
                    config: MaskSearchConfig = MaskSearchConfig()):
    """Cameras (roll 0, focal point at position_w) putting a pitch circle on an image ellipse.

    The circle's angular size from the focal point and the ellipse's major axis give f (to
    within the stretch off the image centre, so a range of f around it is tried); the camera
    is then turned (roll 0) so that the ray through the ellipse centre meets the circle centre.
    These are rough (the ellipse centre is not the image of the circle centre): fit them to
    the ellipse's pixels before use (:func:`reinit_from_mask` does).

    Returns:
        pans_rad, tilts_rad, focals_px: (K,) each; ellipse_index (K,) ints; circle_names: list of K names.
    """
    W, H = frame_size
    C = np.asarray(position_w, float)
    tilt_lo, tilt_hi = np.radians(config.tilt_range_deg)
    circles = [(name, element) for name, element in pitch.elements.items() if isinstance(element, Arc)]
    pans, tilts, focals, which, names = [], [], [], [], []
    for index, ellipse in enumerate(ellipses):
        u, v = ellipse.centre_px - [W / 2.0, H / 2.0]
        for name, circle in circles:
            direction = np.asarray(circle.centre_w, float) - C
            distance = np.linalg.norm(direction)
            if distance < 2 * circle.radius_m or direction[2] <= 0:
                continue
            focal = ellipse.semi_axes_px[0] / math.tan(math.asin(circle.radius_m / distance))
            for f in focal * np.asarray(config.ellipse_focal_factors):
                if not (config.line_focal_range_per_width[0] * W < f < config.line_focal_range_per_width[1] * W):
                    continue
                for pan, tilt in _pointing(direction, np.array([u, v, f])):
                    if tilt_lo < tilt < tilt_hi:
                        pans.append(pan), tilts.append(tilt), focals.append(f), which.append(index), names.append(name)
    return np.array(pans), np.array(tilts), np.array(focals), np.array(which, int), names


def _distinct(pans, tilts, focals, costs, count: int, radius_px: float, width_px: int) -> list[int]:
    """Indices of up to ``count`` best (lowest cost) hypotheses, no two within radius_px (frame pixels) of each other."""
    order = np.argsort(costs)
    kept: list[int] = []
    for k in order:
        if not np.isfinite(costs[k]):
            break
        f = focals[k]
        close = False
        for m in kept:
            shift = max(abs(pans[k] - pans[m]) * f, abs(tilts[k] - tilts[m]) * f,
                        abs(math.log(f / focals[m])) * width_px / 2)
            if shift < radius_px:
                close = True
                break
        if not close:
            kept.append(int(k))
            if len(kept) >= count:
                break
    return kept


def _image_distance_px(a: Camera, b: Camera, points_w: np.ndarray) -> float:
    """Median pixel distance between the projections by two cameras of the points either shows (inf if none)."""
    uv_a, front_a = a.project(points_w)
    uv_b, front_b = b.project(points_w)
    shown = front_a & front_b & (a.in_image(uv_a) | b.in_image(uv_b))
    return float(np.median(np.linalg.norm(uv_a[shown] - uv_b[shown], axis=1))) if shown.any() else math.inf


def _refine_on_map(camera: Camera, points_px: np.ndarray, position_w, curves: TemplateCurves,
                   config: MaskSearchConfig, schedule: RefineSchedule) -> Camera:
    """Label-and-fit rounds with a shrinking gate and a robust scale tied to it (:class:`RefineSchedule`)."""
    W = camera.width_px
    base = LineFitConfig(polish_power=0.0, iterations=schedule.iterations, sigma_position_m=config.position_sigma_m,
                         sigma_k1=config.sigma_k1)
    gates = schedule.gates_per_width
    for round_index, gate in enumerate(gates):
        lines = label_points_by_camera(camera, points_px, curves, gate * W)
        if sum(len(p) for p in lines.values()) < 8:
            break
        scale = min(max(schedule.cauchy_per_gate * gate, schedule.cauchy_min_per_width), schedule.cauchy_max_per_width)
        # k1 is held at 0 in the first rounds: with a wrong labelling it trades against f and drifts.
        fixed = () if round_index >= min(schedule.k1_free_from_round, len(gates) - 1) else (1,)
        if len(lines) < config.min_classes_free_position:
            fixed = (1, 5, 6, 7)  # one or two markings (a circle alone): the focal point and k1 are not observable
        camera = fit_camera_to_lines(camera, lines, curves, replace(base, cauchy_scale_px=scale * W),
                                     position_prior_w=np.asarray(position_w), fixed=fixed).camera
    return camera


@dataclass
class _Hypothesis:
    """A roll-0, k1-0 camera proposed from the marking map: focal point (3,), pan, tilt (radians), f (pixels),
    cost (-F_beta of :class:`_MapScorer`, lower is better) and, for line-pair cameras, the pair (else None)."""

    position_w: np.ndarray
    pan_rad: float
    tilt_rad: float
    focal_px: float
    cost: float
    pair: LinePairs | None = None


def _line_pair_hypotheses(lines, position_w, frame_size, pitch, lines_w, scorer: _MapScorer,
                          config: MaskSearchConfig, steps: np.ndarray) -> list[_Hypothesis]:
    """Line-pair cameras at one focal point: all scored coarsely, the best distinct ones moved along f and rescored."""
    W, _ = frame_size
    C = np.asarray(position_w, float)
    pairs = line_pair_cameras(lines, C, frame_size, pitch, config, lines_w)
    if not len(pairs.focals_px):
        return []
    coarse = scorer.costs(C, pairs.pans_rad, pairs.tilts_rad, pairs.focals_px, config.coarse_hit_px,
                          config.coarse_point_px, thin=config.coarse_thin)
    chosen = pairs.subset(np.asarray(_distinct(pairs.pans_rad, pairs.tilts_rad, pairs.focals_px, coarse,
                                               config.polish_top_k, config.distinct_per_width * W, W), int))
    polished, costs = _best_along_focal(_PairGeometry(lines, C, frame_size, lines_w), chosen, C, scorer, config, steps)
    return [_Hypothesis(C, polished.pans_rad[k], polished.tilts_rad[k], polished.focals_px[k], costs[k],
                        polished.subset([k])) for k in np.nonzero(np.isfinite(costs))[0]]


def _circle_hypotheses(ellipses: list[ImageEllipse], points_px: np.ndarray, positions, frame_size, pitch,
                       curves: TemplateCurves, scorer: _MapScorer, config: MaskSearchConfig) -> list[_Hypothesis]:
    """Circle cameras: for each focal point, ellipse and circle the rough camera (:func:`ellipse_cameras`)
    whose projected circle lies closest to the ellipse's points; the ``ellipse_fit_top_k`` closest are
    fitted to those points (f, pan, tilt; the focal point, roll and k1 held) and scored."""
    W, H = frame_size
    band = 3.0 * config.ellipse_band_px * W / 960.0
    on_ellipse = []
    for ellipse in ellipses:
        on = points_px[ellipse.distances_px(points_px) < band]
        on_ellipse.append(on[np.linspace(0, len(on) - 1, min(len(on), config.ellipse_fit_points)).astype(int)])
    samples = pitch.sample_uniform(1.0)
    closest: dict[tuple, tuple] = {}
    for C in positions:
        pans, tilts, focals, which, names = ellipse_cameras(ellipses, C, frame_size, pitch, config)
        for k in range(len(pans)):
            on = on_ellipse[which[k]]
            if len(on) < 8:
                continue
            camera = Camera(focals[k], 0.0, pans[k], tilts[k], 0.0, np.asarray(C, float), W, H)
            uv, front = camera.project(samples[names[k]])
            if front.sum() < 3:
                continue
            gap = float(np.median(np.min(np.linalg.norm(on[:, None, :] - uv[front][None, :, :], axis=2), axis=1)))
            key = (tuple(C), int(which[k]), names[k])
            if key not in closest or gap < closest[key][0]:
                closest[key] = (gap, camera)
    fit_config = LineFitConfig(polish_power=0.0, iterations=10, cauchy_scale_px=config.ellipse_band_px * W / 960.0)
    out = []
    for (C, which, name), (_, camera) in sorted(closest.items(), key=lambda item: item[1][0])[: config.ellipse_fit_top_k]:
        camera = fit_camera_to_lines(camera, {name: on_ellipse[which]}, curves, fit_config, fixed=(1, 4, 5, 6, 7)).camera
        cost = scorer.costs(C, [camera.pan_rad], [camera.tilt_rad], [camera.focal_px], config.score_hit_px,
                            config.score_point_px)[0]
        if np.isfinite(cost):
            out.append(_Hypothesis(np.asarray(C, float), camera.pan_rad, camera.tilt_rad, camera.focal_px, cost))
    return out


def reinit_from_mask(
    marking_mask: np.ndarray,
    marking_points_px: np.ndarray,
    frame_size: tuple[int, int],
    pitch: PitchTemplate | None = None,
    positions_w=None,
    config: MaskSearchConfig = MaskSearchConfig(),
    curves: TemplateCurves | None = None,
    field_mask: np.ndarray | None = None,
) -> ReinitResult:
    """Weight-free re-initialisation: camera hypotheses from the structure of the marking map, scored, then fitted.

    1. Hypotheses (roll 0, k1 0) at each candidate focal point (default: the default tripods, not
       mirrored: the map has no labels and the pitch is symmetric): pairs of straight markings
       put on pairs of pitch lines (:func:`marking_lines`, :func:`line_pair_cameras`; any zoom,
       f from a grid then moved along each pair's family), and a pitch circle put on an ellipse
       of the map (:func:`marking_ellipses`, :func:`ellipse_cameras`; the centre circle alone);
       optionally the coarse grid of :func:`mask_search`. When nothing scores ``poor_score`` at
       the default tripods, ``far_positions_w`` (main cameras further back and higher) are tried.
    2. Every hypothesis gets one score, -F_beta of the template found in the map (recall) and the
       marking points explained by the template (precision, through the pitch plane)
       (:class:`_MapScorer`); the first candidate position is preferred on near ties.
    3. The best distinct hypotheses are fitted in turn (:func:`_refine_on_map`: name the marking
       points by the nearest projected class, :func:`fit_camera_to_lines`, shrinking gate; the
       wide schedule as well on poorly scoring ones) and ranked by a fine fit score; the
       best-scoring hypothesis is kept unless a later one fits ``switch_margin`` better.

    The returned score is the confidence of the camera (``score.jaccard``,
    confidence.camera_confidence).

    Args:
        marking_mask: bool marking map (frame size or a reduced size of the same aspect ratio).
        marking_points_px: (M, 2) centre-line points, frame pixels.
        frame_size: (W, H) of the frame (the camera's resolution).
        positions_w: candidate focal points (metres); None = :data:`DEFAULT_TRIPOD_POSITIONS_W` (and the
            far positions when they fit poorly).
        field_mask: optional bool map of the playing surface (for the confidence).

    Returns:
        ReinitResult with the camera at frame_size, or camera None and a reason.
    """
    from broadtrack_graph.reinit.confidence import camera_confidence

    pitch = pitch or PitchTemplate()
    curves = curves or TemplateCurves(pitch)
    W, H = frame_size
    points_px = np.asarray(marking_points_px, float).reshape(-1, 2)
    if not marking_mask.any() or len(points_px) < 10:
        return ReinitResult(None, None, "", "too few marking pixels")
    positions = list(DEFAULT_TRIPOD_POSITIONS_W.values()) if positions_w is None else [tuple(p) for p in positions_w]
    ground = [n for n in pitch.elements if pitch.is_on_ground(n)]
    scorer = _MapScorer(marking_mask, points_px, (W, H), pitch, config)
    lines = marking_lines(marking_mask, W, config)
    lines_w = pitch_lines(pitch)
    ratio = (config.line_focal_range_per_width[1] / config.line_focal_range_per_width[0]) ** (
        1.0 / max(config.line_focal_count - 1, 1))
    steps = ratio ** np.linspace(-1.0, 1.0, config.polish_focal_steps)
    hypotheses: list[_Hypothesis] = []
    for position in positions:
        hypotheses += _line_pair_hypotheses(lines, position, (W, H), pitch, lines_w, scorer, config, steps)
        if config.grid_top_k:
            grid_samples_w = np.vstack(list(pitch.sample_uniform(config.template_step_m, classes=ground).values()))
            for _, camera in mask_search(marking_mask, position, (W, H), pitch, config, grid_samples_w):
                cost = scorer.costs(position, [camera.pan_rad], [camera.tilt_rad], [camera.focal_px],
                                    config.score_hit_px, config.score_point_px)[0]
                hypotheses.append(_Hypothesis(np.asarray(position, float), camera.pan_rad, camera.tilt_rad,
                                              camera.focal_px, cost))
    if positions_w is None and (not hypotheses or -min(h.cost for h in hypotheses) < config.poor_score):
        # A poor fit at every guess: main cameras of larger stadiums stand further back and higher, on about
        # the same line of sight to the centre spot (the images along it differ mostly by f).
        for position in config.far_positions_w:
            hypotheses += _line_pair_hypotheses(lines, position, (W, H), pitch, lines_w, scorer, config, steps)
    ellipses = marking_ellipses(marking_mask, W, config) if config.max_ellipses else []
    if ellipses:
        hypotheses += _circle_hypotheses(ellipses, points_px, positions, (W, H), pitch, curves, scorer, config)
    if not hypotheses:
        return ReinitResult(None, None, "", "no hypothesis from the marking map")
    # The first candidate (the main camera by default) is the likelier one when scores are about equal.
    first = np.asarray(positions[0], float)
    costs = np.array([h.cost * (1.0 if np.allclose(h.position_w, first) else config.other_position_factor)
                      for h in hypotheses])
    chosen = _distinct(np.array([h.pan_rad for h in hypotheses]), np.array([h.tilt_rad for h in hypotheses]),
                       np.array([h.focal_px for h in hypotheses]), costs, config.refine_top_k,
                       config.distinct_per_width * W, W)
    log.debug("mask re-init: %d lines, %d ellipses, %d hypotheses", len(lines), len(ellipses), len(hypotheses))
    points = points_px
    if len(points) > config.max_fit_points:
        points = points[np.linspace(0, len(points) - 1, config.max_fit_points).astype(int)]
    fine = _MapScorer(marking_mask, points_px, (W, H), pitch,
                      replace(config, score_template_step_m=config.fit_template_step_m,
                              score_max_points=config.fit_max_points))
    check_w = np.vstack(list(pitch.sample_uniform(4.0, classes=ground).values()))
    best = None  # (fit score, camera, focal point, whether from the first fitted hypothesis)
    refined: list[Camera] = []
    for k in chosen:
        hypothesis = hypotheses[k]
        if costs[k] > config.refine_cost_share * costs[chosen[0]] or len(refined) >= config.max_fits:
            break  # no close competitor of the best-scoring hypothesis left, or enough fits
        C = hypothesis.position_w
        start = Camera(hypothesis.focal_px, 0.0, hypothesis.pan_rad, hypothesis.tilt_rad, 0.0, C, W, H)
        if any(_image_distance_px(start, other, check_w) < config.distinct_per_width * W for other in refined):
            continue  # a fit already landed here
        camera = _refine_on_map(start, points, C, curves, config, config.schedule)
        refined.append(camera)
        score = -fine.camera_cost(camera, config.fit_hit_px, config.fit_point_px)
        if (config.wide_schedule is not None and -hypothesis.cost < config.wide_below_score
                and len(refined) < config.max_fits):
            # A poor fit at the guessed focal point: the camera may stand metres away, leaving the hypothesis
            # 10-20 px off, out of reach of the tight fit; one whose robust scale starts wide reaches it.
            wide = _refine_on_map(start, points, C, curves, config, config.wide_schedule)
            refined.append(wide)
            wide_score = -fine.camera_cost(wide, config.fit_hit_px, config.fit_point_px)
            if wide_score > score:
                camera, score = wide, wide_score
        # The best-scoring hypothesis is kept unless a later one fits clearly better: on sparse or blurred
        # markings a fit can slide along the focal length / distance trade-off onto clutter, or push
        # undetected markings out of the image, and look a little better.
        if best is None or score > best[0] + (config.switch_margin if best[3] else 0.0):
            best = (score, camera, C, best is None)
        if score >= config.accept_fit_score:
            break
    if best is None:
        return ReinitResult(None, None, "", "no hypothesis could be fitted", len(hypotheses))
    _, camera, position, _ = best
    jac = camera_confidence(camera, marking_mask, curves, field_mask=field_mask)
    return ReinitResult(camera, LabelledScore(jac, 0, 0, 0, 0.0, 0.0),
                        f"mask search at {tuple(round(float(v)) for v in position)}", tried=len(hypotheses))


def label_points_by_camera(camera: Camera, points_px: np.ndarray, curves: TemplateCurves, gate_px: float,
                           classes=None) -> dict[str, np.ndarray]:
    """Name unlabelled marking points by their nearest projected ground class within gate_px."""
    names = [n for n in (classes or curves.samples_w) if curves.pitch.is_on_ground(n)]
    best_d = np.full(len(points_px), np.inf)
    best_c = np.full(len(points_px), -1)
    for j, name in enumerate(names):
        uv, front = camera.project(curves.samples_w[name])
        ok = front & camera.in_image(uv)
        if ok.sum() < 2:
            continue
        valid = ok[:-1] & ok[1:]
        if not valid.any():
            continue
        _, _, d = closest_on_polyline(points_px, uv, valid)
        better = d < best_d
        best_d[better], best_c[better] = d[better], j
    out = {}
    for j, name in enumerate(names):
        sel = (best_c == j) & (best_d < gate_px)
        if sel.sum() >= 3:
            out[name] = points_px[sel]
    return out
