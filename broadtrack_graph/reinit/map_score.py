"""The map score of roll-0 camera hypotheses: -F_beta of the template found in the marking map (recall)
and the marking points explained by the template (precision), and the choice of the best distinct ones. No I/O.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.reinit.mask_config import MaskSearchConfig


def _distance_map(marking_mask: np.ndarray, work_width_px: int, cap_px: float, frame_width_px: int):
    """Capped distance transform of the marking map at the working width, and working / frame pixel scale."""
    H, W = marking_mask.shape
    w = min(work_width_px, W)
    h = max(1, int(round(H * w / W)))
    small = cv2.resize(marking_mask.astype(np.uint8) * 255, (w, h), interpolation=cv2.INTER_AREA) > 0
    dt = cv2.distanceTransform((~small).astype(np.uint8), cv2.DIST_L2, 3)
    return np.minimum(dt, cap_px).astype(np.float32), w / frame_width_px


@functools.lru_cache(maxsize=4)
def _ground_template_map(dimensions, resolution_m: float = 0.1):
    """Nearest painted ground marking of every cell of a grid over the pitch (and 8 m around it).

    Returns:
        nearest_xy_w: (h, w, 2) float32 metres, the nearest marking point of each cell;
        origin_w: (2,) metres of cell (0, 0); resolution_m;
        nearest_x, nearest_y: (h * w,) the two coordinates apart, flat (np.take on a contiguous array is the
        quick gather).
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
    nearest = zero_xy[labels - 1]
    return (nearest, origin, resolution_m, np.ascontiguousarray(nearest[..., 0]).ravel(),
            np.ascontiguousarray(nearest[..., 1]).ravel())


@functools.lru_cache(maxsize=8)
def _ground_samples(dimensions, step_m: float) -> np.ndarray:
    """(S, 3) metres: the painted ground markings sampled ``step_m`` apart (read only)."""
    pitch = PitchTemplate(dimensions)
    ground = [n for n in pitch.elements if pitch.is_on_ground(n)]
    samples = np.vstack(list(pitch.sample_uniform(step_m, classes=ground).values()))
    samples.flags.writeable = False
    return samples


class MapScorer:
    """Scores roll-0 cameras against one marking map: cost = -F_beta(precision, recall) (lower is better).

    recall: template length (working pixels, samples ``score_template_step_m`` apart) within
    ``hit_px`` of a marking pixel, over the template length in the image (at least
    ``score_min_template_px``); precision: share of the marking points whose ray meets the pitch
    near a painted marking that projects back within ``point_px`` of the point. Pixel sizes at
    ``score_work_width_px``; beta is ``score_beta``.
    """

    def __init__(self, marking_mask: np.ndarray, marking_points_px: np.ndarray, frame_size, pitch: PitchTemplate,
                 config: MaskSearchConfig, same_map_as: "MapScorer | None" = None):
        """same_map_as: a scorer of the same marking map and frame size whose distance map is taken when its
        working width and cap are this config's too (two scorers of one frame)."""
        self.W, self.H = frame_size
        self.config = config
        if same_map_as is not None and (same_map_as.config.score_work_width_px, same_map_as.config.score_cap_px) == (
                config.score_work_width_px, config.score_cap_px) and (same_map_as.W, same_map_as.H) == (self.W, self.H):
            self.dt, self.scale = same_map_as.dt, same_map_as.scale
        else:
            self.dt, self.scale = _distance_map(marking_mask, config.score_work_width_px, config.score_cap_px, self.W)
        self.samples_w = _ground_samples(pitch.dimensions, config.score_template_step_m)
        points = np.asarray(marking_points_px, float).reshape(-1, 2)
        if len(points) > config.score_max_points:
            points = points[np.linspace(0, len(points) - 1, config.score_max_points).astype(int)]
        self.points_c = points - [self.W / 2.0, self.H / 2.0]
        self.nearest_xy, self.origin, self.resolution, self.nearest_x_flat, self.nearest_y_flat = \
            _ground_template_map(pitch.dimensions)

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
            out[s:s + chunk] = _chunk_costs(precision, recall, inside.sum(axis=1), thin, b2)
        return out


    def plane_costs(self, H_px: np.ndarray, sign: np.ndarray, px_per_m_at_unit: np.ndarray, hit_px: float,
                    point_px: float, chunk: int = 256, thin: int = 1, best: int | None = None) -> np.ndarray:
        """(K,) costs of ground-plane homographies, any camera (the same score as :meth:`costs`, no distortion).

        Args:
            H_px: (K, 3, 3) pitch (x, y, 1) metres -> frame pixels.
            sign: (K,) +-1: a ground point X is in front of the camera when ``sign * (H_px X)_z > 0``.
            px_per_m_at_unit: (K,) frame pixels per metre of a marking at ``sign * (H_px X)_z = 1`` (f over the
                depth scale): a sample's image length is this over ``sign * (H_px X)_z``.
            thin: use every thin-th template sample and marking point (a quicker, coarser score).
            best: only the ``best`` lowest costs are asked for: the recall of every homography is read first, and
                the precision only of those whose recall alone (with a precision of 1) could score among the best
                read so far; the others' costs are inf (None: every cost).
        """
        recall, shown = self._plane_recalls(H_px, sign, px_per_m_at_unit, hit_px, chunk, thin)
        b2 = self.config.score_beta ** 2
        out = np.full(len(H_px), np.inf)
        if best is None or best >= len(H_px):
            order, bounds = np.arange(len(H_px)), None
        else:
            # F_beta rises with the precision: at a precision of 1 it bounds the score from above.
            bounds = -_chunk_costs(np.ones_like(recall), recall, shown, thin, b2)
            order = np.argsort(-bounds, kind="stable")
            order = order[np.isfinite(bounds[order])]
        step = chunk if bounds is None else max(1, min(chunk, best))  # the bound is asked again after each step
        for s in range(0, len(order), step):
            if bounds is not None and s >= best:
                # Stop when the best-th score read so far beats every bound left.
                kth = -np.partition(out[order[:s]], best - 1)[best - 1]
                if kth > bounds[order[s]]:
                    break
            k = order[s:s + step]
            precision = self._plane_precisions(H_px[k], sign[k], point_px, thin)
            out[k] = _chunk_costs(precision, recall[k], shown[k], thin, b2)
        return out

    def _plane_recalls(self, H_px, sign, px_per_m_at_unit, hit_px: float, chunk: int, thin: int):
        """(K,) recall of each homography's template in the map (:meth:`plane_costs`), and (K,) how many of its
        template samples land in the image (the recalls read chunk by chunk: no (K, S) array is kept)."""
        dt, scale, config = self.dt, self.scale, self.config
        h, w = dt.shape
        dt_flat = dt.ravel()
        samples = self.samples_w[::thin]
        x, y = samples[:, 0], samples[:, 1]  # (S,) ground samples (metres)
        samples_h = np.vstack([x, y, np.ones_like(x)])  # (3, S)
        recall = np.zeros(len(H_px))
        shown = np.zeros(len(H_px), int)
        for s in range(0, len(H_px), chunk):
            Hk, sg = H_px[s:s + chunk], sign[s:s + chunk, None]
            k = len(Hk)
            # The template samples into the image: (k, S) homogeneous pixels (one matrix product for the chunk).
            uw, vw, zw = (Hk.reshape(-1, 3) @ samples_h).reshape(k, 3, -1).transpose(1, 0, 2)
            depth = sg * zw
            front = depth > 1e-9
            with np.errstate(divide="ignore", invalid="ignore"):
                inv = scale / zw
                u = uw * inv
                v = vw * inv
                inside = front & (u >= 0) & (u < w - 1) & (v >= 0) & (v < h - 1)
                index = np.where(inside, v.astype(np.int32) * w + u.astype(np.int32), 0)
                length = np.where(inside, px_per_m_at_unit[s:s + chunk, None] * scale * config.score_template_step_m
                                  * thin / depth, 0.0)
            d = np.take(dt_flat, index)
            recall[s:s + chunk] = np.sum(length * (d <= hit_px), axis=1) / np.maximum(
                np.sum(length, axis=1), config.score_min_template_px)
            shown[s:s + chunk] = inside.sum(axis=1)
        return recall, shown

    def _plane_precisions(self, Hk: np.ndarray, sign: np.ndarray, point_px: float, thin: int) -> np.ndarray:
        """(k,) precision of each homography (:meth:`plane_costs`): the share of the marking points that meet the
        pitch near a painted marking whose image lies within ``point_px`` of them (1 with no points)."""
        points = self.points_c[::thin] + [self.W / 2.0, self.H / 2.0]
        if not len(points):
            return np.ones(len(Hk))
        pu, pv = points[:, 0], points[:, 1]  # (M,) marking points (frame pixels)
        points_h = np.vstack([pu, pv, np.ones_like(pu)])  # (3, M)
        grid_h, grid_w = self.nearest_xy.shape[:2]
        tol2 = (point_px / self.scale) ** 2
        k, sg = len(Hk), sign[:, None]
        # Marking points onto the pitch (H^-1), to their nearest painted marking, and back (H).
        bx, by, bz = (np.linalg.inv(Hk).reshape(-1, 3) @ points_h).reshape(k, 3, -1).transpose(1, 0, 2)
        ahead = sg * bz > 1e-12
        wz = np.where(ahead, bz, 1.0)
        col = np.rint((bx / wz - self.origin[0]) / self.resolution).astype(np.int64)
        row = np.rint((by / wz - self.origin[1]) / self.resolution).astype(np.int64)
        on_grid = ahead & (col >= 0) & (col < grid_w) & (row >= 0) & (row < grid_h)
        cell = np.where(on_grid, row * grid_w + col, 0)
        nx, ny = np.take(self.nearest_x_flat, cell), np.take(self.nearest_y_flat, cell)  # (k, M) metres
        Hc = [[Hk[:, i, j, None] for j in range(3)] for i in range(3)]  # (k, 1) entries
        fz = Hc[2][0] * nx + Hc[2][1] * ny + Hc[2][2]
        ok = on_grid & (sg * fz > 1e-12)
        fz = np.where(ok, fz, 1.0)
        du = (Hc[0][0] * nx + Hc[0][1] * ny + Hc[0][2]) / fz - pu
        dv = (Hc[1][0] * nx + Hc[1][1] * ny + Hc[1][2]) / fz - pv
        return np.mean(ok & (du * du + dv * dv < tol2), axis=1)


def _chunk_costs(precision: np.ndarray, recall: np.ndarray, shown: np.ndarray, thin: int, beta2: float) -> np.ndarray:
    """(k,) costs -F_beta of precision and recall (k,) (0 where both are 0; beta2 is beta squared), inf for a camera
    with too few template samples in the image (shown: (k,) how many land in it)."""
    with np.errstate(invalid="ignore", divide="ignore"):
        score = np.where(precision + recall > 0, (1 + beta2) * precision * recall / (beta2 * precision + recall), 0.0)
    cost = -score
    cost[shown < max(4, 8 // thin)] = np.inf
    return cost


@dataclass
class Hypothesis:
    """A roll-0, k1-0 camera proposed from the marking map: focal point position_w (3,) metres, pan_rad and
    tilt_rad (radians), focal_px (pixels), cost (-F_beta of :class:`MapScorer`, lower is better)."""

    position_w: np.ndarray
    pan_rad: float
    tilt_rad: float
    focal_px: float
    cost: float


def polish_locally(hypotheses: list[Hypothesis], scorer: MapScorer, config: MaskSearchConfig, width_px: int,
                   weights: np.ndarray | None = None) -> list[Hypothesis]:
    """The best distinct hypotheses moved to the nearby (pan, tilt, f) that the map scores best.

    A hypothesis is exact only at the focal point it was made at: a line pair at a guessed tripod
    a few metres off leaves the rest of the template 10-30 px from the markings, and a right but
    shifted camera then scores below a wrong one that happens to fit where it was made. The
    ``local_polish_top_k`` best distinct hypotheses (ranked by ``cost * weight``) get a pattern
    search: the 27 cameras one step either side in pan, tilt and log f (a step moves the image
    by ``local_polish_step_per_width`` of the width), all scored at once (:meth:`MapScorer.costs`);
    move to the best, halve the step when none is better, stop under
    ``local_polish_min_step_per_width``. Focal point, roll and k1 are held.

    Args:
        hypotheses: the candidates (any focal points).
        weights: (N,) factor on each cost for the ranking (default 1).

    Returns:
        The hypotheses, the polished ones replaced (same order).
    """
    if not hypotheses or config.local_polish_top_k <= 0:
        return hypotheses
    weights = np.ones(len(hypotheses)) if weights is None else np.asarray(weights, float)
    chosen = best_distinct(np.array([h.pan_rad for h in hypotheses]), np.array([h.tilt_rad for h in hypotheses]),
                           np.array([h.focal_px for h in hypotheses]),
                           np.array([h.cost for h in hypotheses]) * weights, config.local_polish_top_k,
                           config.distinct_per_width * width_px, width_px)
    grid = np.array(np.meshgrid([-1.0, 0.0, 1.0], [-1.0, 0.0, 1.0], [-1.0, 0.0, 1.0], indexing="ij")).reshape(3, -1)
    # Each chosen hypothesis's pattern search: [pan, tilt, f, cost, step]. The searches run side by side, those at
    # one focal point scored in one call per round (each camera's score is its own: the same moves as one by one).
    searches = {k: [hypotheses[k].pan_rad, hypotheses[k].tilt_rad, hypotheses[k].focal_px, hypotheses[k].cost,
                    config.local_polish_step_per_width * width_px] for k in chosen}
    min_step_px = config.local_polish_min_step_per_width * width_px
    active = [k for k in chosen if searches[k][4] >= min_step_px]
    while active:
        at_position: dict[tuple, list[int]] = {}
        for k in active:
            at_position.setdefault(tuple(np.asarray(hypotheses[k].position_w, float)), []).append(k)
        for ks in at_position.values():
            pans, tilts, focals = [], [], []
            for k in ks:
                pan, tilt, focal, _, step_px = searches[k]
                angle, factor = step_px / focal, 1.0 + step_px / (width_px / 2.0)
                pans.append(pan + grid[0] * angle)
                tilts.append(tilt + grid[1] * angle)
                focals.append(focal * factor ** grid[2])
            pans, tilts, focals = np.stack(pans), np.stack(tilts), np.stack(focals)  # (searches, 27)
            costs = scorer.costs(hypotheses[ks[0]].position_w, pans.ravel(), tilts.ravel(), focals.ravel(),
                                 config.score_hit_px, config.score_point_px).reshape(pans.shape)
            for row, k in enumerate(ks):
                j = int(np.argmin(costs[row]))
                search = searches[k]
                if costs[row, j] < search[3] - 1e-9:
                    search[:4] = [float(pans[row, j]), float(tilts[row, j]), float(focals[row, j]),
                                  float(costs[row, j])]
                else:
                    search[4] /= 2.0
        active = [k for k in active if searches[k][4] >= min_step_px]
    out = list(hypotheses)
    for k, (pan, tilt, focal, cost, _) in searches.items():
        out[k] = Hypothesis(hypotheses[k].position_w, pan, tilt, focal, cost)
    return out


def best_distinct(pans, tilts, focals, costs, count: int, radius_px: float, width_px: int) -> list[int]:
    """Indices of up to ``count`` best (lowest cost) hypotheses, no two within radius_px (frame pixels) of each other
    (pans compared round the circle: -179 and 179 deg are 2 deg apart)."""
    order = np.argsort(costs)
    kept: list[int] = []
    for k in order:
        if not np.isfinite(costs[k]):
            break
        f = focals[k]
        close = False
        for m in kept:
            shift = max(abs(math.remainder(pans[k] - pans[m], 2 * math.pi)) * f, abs(tilts[k] - tilts[m]) * f,
                        abs(math.log(f / focals[m])) * width_px / 2)
            if shift < radius_px:
                close = True
                break
        if not close:
            kept.append(int(k))
            if len(kept) >= count:
                break
    return kept
