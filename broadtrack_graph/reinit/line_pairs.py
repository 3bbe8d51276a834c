"""Line-pair hypotheses: cameras (roll about 0, focal point fixed) that put two straight markings of the
map on two pitch lines, at any zoom (f gridded, then moved along each pair's family). No I/O.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.detect.marking_structures import ImageLine
from broadtrack_graph.geometry.matrices import cross3
from broadtrack_graph.geometry.pitch import PitchTemplate, Segment
from broadtrack_graph.reinit.map_score import Hypothesis, MapScorer, best_distinct
from broadtrack_graph.reinit.mask_config import MaskSearchConfig


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
    return np.stack([e1, e2, cross3(e1, e2)], axis=2)


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

    def subset(self, keep) -> LinePairs:
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
        normals_w = cross3(self.directions_w, self.points_w - self.C)
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


def _best_along_focal(geometry: _PairGeometry, pairs: LinePairs, position_w, scorer: MapScorer,
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


def line_pair_hypotheses(lines, position_w, frame_size, pitch, lines_w, scorer: MapScorer,
                          config: MaskSearchConfig, steps: np.ndarray) -> list[Hypothesis]:
    """Line-pair cameras at one focal point: all scored coarsely, the best distinct ones moved along f and rescored."""
    W, _ = frame_size
    C = np.asarray(position_w, float)
    pairs = line_pair_cameras(lines, C, frame_size, pitch, config, lines_w)
    if not len(pairs.focals_px):
        return []
    coarse = scorer.costs(C, pairs.pans_rad, pairs.tilts_rad, pairs.focals_px, config.coarse_hit_px,
                          config.coarse_point_px, thin=config.coarse_thin)
    chosen = pairs.subset(np.asarray(best_distinct(pairs.pans_rad, pairs.tilts_rad, pairs.focals_px, coarse,
                                               config.polish_top_k, config.distinct_per_width * W, W), int))
    polished, costs = _best_along_focal(_PairGeometry(lines, C, frame_size, lines_w), chosen, C, scorer, config, steps)
    return [Hypothesis(C, polished.pans_rad[k], polished.tilts_rad[k], polished.focals_px[k], costs[k])
            for k in np.nonzero(np.isfinite(costs))[0]]
