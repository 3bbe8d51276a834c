"""Camera hypotheses from straight markings alone, wherever the camera stands (court-model calibration). No I/O.

The pitch's straight markings fall in two families: lines parallel to the touchlines (``y = c``)
and lines parallel to the goal lines (``x = c``). In the image each family's lines meet at a
vanishing point, and the ground-plane homography ``H = K [r1 r2 t]`` (pitch ``(x, y, 1)`` metres ->
pixels) has those vanishing points as its first two columns: ``h1 ~ v_x``, ``h2 ~ v_y``. What the
line correspondences add is one number per line. Every line of the ``y = c`` family passes through
``v_x``, so with the pencil coordinate ``tau = (q . l) / (v_y . l)`` (``q`` the image centre; the
horizon, through both vanishing points, is ``tau = inf``) the pitch offset of the line is affine in
tau, ``c = a tau + b``, and likewise for the other family. Two lines of a family put on two pitch
lines fix its ``(a, b)``; one such pair per family fixes H:

    H = [-v_x / a_y, -v_y / a_x, q + (b_x / a_x) v_y + (b_y / a_y) v_x]

(``a_x, b_x`` of the ``y = c`` family, ``a_y, b_y`` of the ``x = c`` family). Every pairing of two
image lines of each family with two pitch lines of that family is a hypothesis, all formed at once, each
with the vanishing points of its own lines (where its two lines of a family meet: a line that joined the
family without being a pitch line bends no other hypothesis). Two conditions every camera's homography meets are
asked first, of many pairings at once: some focal length in range makes the two vanishing points' directions
orthogonal (:func:`orthogonal_in_range`) and the two axes of equal norm (:func:`equal_norms_in_range`), within the
gate's mismatch; a pairing failing either is not formed.
:func:`cameras_from_homographies` turns the homographies into cameras (principal point at the
image centre, square pixels: ``f`` from the orthogonality and equal norm of ``K^-1 h1`` and
``K^-1 h2``) and gates them on plausibility. The families themselves (which image lines run along which pitch
direction): :mod:`broadtrack_graph.reinit.court_families`. Lens distortion is ignored here (the fit that follows
frees k1).

Image coordinates inside this module are normalised: ``x_n = (u - W / 2) / s``, ``y_n = (v - H / 2) / s``
with ``s = W / 2``. Pitch frame: SoccerNet (metres, origin at the centre spot, z down).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.geometry.matrices import cross3
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.state import angles_from_rotations
from broadtrack_graph.reinit.court_families import CourtLineConfig, LineFamilies


def pitch_line_offsets(pitch: PitchTemplate) -> tuple[np.ndarray, np.ndarray]:
    """The offsets (metres) of the straight ground markings: ``y = c`` lines (parallel to the touchlines) and
    ``x = c`` lines (parallel to the goal lines), each sorted, every painted line counted once (read only)."""
    return _line_offsets(pitch.dimensions)


@functools.lru_cache(maxsize=8)
def _line_offsets(dimensions) -> tuple[np.ndarray, np.ndarray]:
    """:func:`pitch_line_offsets` of the pitch of these dimensions (asked once per pitch)."""
    pitch = PitchTemplate(dimensions)
    along_x, along_y = set(), set()
    for name, element in pitch.elements.items():
        if not pitch.is_on_ground(name) or not hasattr(element, "start_w"):
            continue
        a, b = np.asarray(element.start_w, float), np.asarray(element.end_w, float)
        if abs(a[1] - b[1]) < 1e-9:
            along_x.add(round(float(a[1]), 4))
        elif abs(a[0] - b[0]) < 1e-9:
            along_y.add(round(float(a[0]), 4))
    offsets = np.array(sorted(along_x)), np.array(sorted(along_y))
    for array in offsets:
        array.flags.writeable = False
    return offsets


@functools.lru_cache(maxsize=16)
def _pairs(count: int) -> tuple[np.ndarray, np.ndarray]:
    """The unordered pairs (i < j) of ``count`` items, as two index arrays (read only)."""
    pairs = np.triu_indices(count, 1)
    for array in pairs:
        array.flags.writeable = False
    return pairs


def pair_maps(tau: np.ndarray, offsets_m: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every ``c = a tau + b`` putting two image lines on two pitch lines, for many line pairs at once.

    Args:
        tau: (..., 2) the pencil coordinates of each pair's two lines.
        offsets_m: (m,) the pitch lines' offsets.

    Returns:
        a, b: (..., m (m - 1)) the maps of every ordered pitch-line pair (both directions of the map); NaN where the
        two lines coincide in tau or a coordinate is not finite.
    """
    p, q = np.nonzero(~np.eye(len(offsets_m), dtype=bool))  # ordered pitch-line pairs
    dt = (tau[..., 1] - tau[..., 0])[..., None]
    with np.errstate(divide="ignore", invalid="ignore"):
        a = np.where(np.abs(dt) > 1e-9, (offsets_m[q] - offsets_m[p]) / dt, np.nan)
        b = offsets_m[p] - a * tau[..., 0:1]
    return a, b


@dataclass(frozen=True)
class PlaneHypotheses:
    """Ground-plane homographies (normalised image coordinates) and the cameras they decompose into.

    H_n: (K, 3, 3) pitch (x, y, 1) metres -> normalised image point; focal_n: (K,) f / s; R_cw: (K, 3, 3);
    C_w: (K, 3) metres; angles_rad: (K, 3) pan, tilt, roll; sign: (K,) +-1, the sign that makes H's image
    points lie in front of the camera (depth of ground point X = sign * (H_n X)_z / scale_m); scale_m: (K,).
    """

    H_n: np.ndarray
    focal_n: np.ndarray
    R_cw: np.ndarray
    C_w: np.ndarray
    angles_rad: np.ndarray
    sign: np.ndarray
    scale_m: np.ndarray

    def __len__(self) -> int:
        return len(self.focal_n)

    def subset(self, selected: np.ndarray) -> "PlaneHypotheses":
        """The hypotheses ``selected`` (a bool mask or indices), in their order."""
        return PlaneHypotheses(*(getattr(self, name)[selected] for name in PlaneHypotheses.__dataclass_fields__))



def line_hypotheses(families: LineFamilies, support_px: np.ndarray, pitch: PitchTemplate, frame_size,
                    config: CourtLineConfig = CourtLineConfig()) -> PlaneHypotheses:
    """Every camera putting two lines of each image family on two pitch lines of one direction each
    (either family as either direction), gated by :func:`cameras_from_homographies`: :func:`split_hypotheses` of one
    split."""
    return split_hypotheses([families], support_px, pitch, frame_size, config)


def split_hypotheses(splits: list[LineFamilies], support_px: np.ndarray, pitch: PitchTemplate, frame_size,
                     config: CourtLineConfig = CourtLineConfig(), max_hypotheses: int | None = None
                     ) -> PlaneHypotheses:
    """The hypotheses of several splits of the lines (:func:`line_hypotheses` of each, one after the other), formed
    at once: every pairing of two lines of each family of every split, all gated together.

    Each hypothesis takes its vanishing points from its own four lines (the two of a family meet at that
    direction's vanishing point), not from all of the family's: a line that joined a family without being
    a pitch line (a banner's edge, a board's base, nearly parallel to the pitch lines in a narrow view, where
    the vanishing point lies far off) does not bend the hypotheses of the lines that are.

    Args:
        splits: the splits, likeliest first (:func:`~.court_families.line_families`).
        support_px: (L,) each line's support (the best supported ``max_lines_per_family`` of a family are paired).
        max_hypotheses: the splits after the one whose plausible hypotheses bring the count to this are left out
            (None: none), as if the splits were formed one by one until then.
    """
    along_x, along_y = pitch_line_offsets(pitch)
    q = np.array([0.0, 0.0, 1.0])
    f_lo, f_hi = (2.0 * v for v in config.focal_range_per_width)  # f / s = 2 f / W
    if len(along_x) < 2 or len(along_y) < 2:
        return cameras_from_homographies(np.zeros((0, 3, 3)), frame_size, pitch, config)
    blocks, block_split = [], []
    for index, families in enumerate(splits):
        for first in (0, 1):  # family `first` is the y = c direction (through v_x), the other x = c
            lines_a = families.lines_n[families.members(first, config.max_lines_per_family, support_px)]
            lines_b = families.lines_n[families.members(1 - first, config.max_lines_per_family, support_px)]
            if len(lines_a) < 2 or len(lines_b) < 2:
                continue
            pairs_a, pairs_b = _pairs(len(lines_a)), _pairs(len(lines_b))
            # every pair of lines_a with every pair of lines_b, the pair of lines_a major: (Pa * Pb, 4, 3)
            of_a = np.repeat(np.arange(len(pairs_a[0])), len(pairs_b[0]))
            of_b = np.tile(np.arange(len(pairs_b[0])), len(pairs_a[0]))
            blocks.append(np.stack([lines_a[pairs_a[0][of_a]], lines_a[pairs_a[1][of_a]],
                                    lines_b[pairs_b[0][of_b]], lines_b[pairs_b[1][of_b]]], axis=1))
            block_split.append(np.full(len(of_a), index))
    if not blocks:
        return cameras_from_homographies(np.zeros((0, 3, 3)), frame_size, pitch, config)
    quads, split_of = np.concatenate(blocks), np.concatenate(block_split)  # (B, 4, 3), (B,)
    v_x = _unit(cross3(quads[:, 0], quads[:, 1]))  # (B, 3): where the pair of each direction meets
    v_y = _unit(cross3(quads[:, 2], quads[:, 3]))
    # Only the pairs of pairs whose meeting points some focal length in range makes orthogonal (within the mismatch)
    # can give a camera, and of their pitch-line assignments only those whose two axes some focal length in range
    # makes of equal norm (within the mismatch): the others are not formed.
    kept = np.nonzero(orthogonal_in_range(v_x, v_y, f_lo, f_hi, config.max_axis_mismatch))[0]
    quads, split_of, v_x, v_y = quads[kept], split_of[kept], v_x[kept], v_y[kept]
    with np.errstate(divide="ignore", invalid="ignore"):
        tau_a = (quads[:, :2] @ q) / np.einsum("bki,bi->bk", quads[:, :2], v_y)  # (B, 2) pencil coordinates
        tau_b = (quads[:, 2:] @ q) / np.einsum("bki,bi->bk", quads[:, 2:], v_x)
    a_x, b_x = pair_maps(tau_a, along_x)  # (B, Ma)
    a_y, b_y = pair_maps(tau_b, along_y)  # (B, Mb)
    k, m, n = np.nonzero(equal_norms_in_range(v_x, v_y, a_x, a_y, f_lo, f_hi, config.max_axis_mismatch))
    H = homographies_from_maps(v_x[k], v_y[k], a_x[k, m], b_x[k, m], a_y[k, n], b_y[k, n])
    finite = np.all(np.isfinite(H), axis=(1, 2))
    hypotheses, placed = plausible_cameras(H[finite], frame_size, pitch, config)
    if max_hypotheses is not None and len(placed):
        of_split = split_of[k[finite][placed]]
        counts = np.cumsum(np.bincount(of_split, minlength=len(splits)))
        last = int(np.searchsorted(counts, max_hypotheses))  # the split that brings the count to max_hypotheses
        hypotheses = hypotheses.subset(of_split <= last)
    return hypotheses


def homographies_from_maps(v_x: np.ndarray, v_y: np.ndarray, a_x: np.ndarray, b_x: np.ndarray, a_y: np.ndarray,
                           b_y: np.ndarray) -> np.ndarray:
    """(..., 3, 3) ``H = [-v_x / a_y, -v_y / a_x, q + (b_x / a_x) v_y + (b_y / a_y) v_x]`` (module docstring), the
    arguments broadcast together: vanishing points (..., 3), the two families' maps (...); inf or NaN where a map is
    degenerate."""
    q = np.array([0.0, 0.0, 1.0])
    with np.errstate(divide="ignore", invalid="ignore"):
        h1 = -v_x / a_y[..., None]
        h2 = -v_y / a_x[..., None]
        h3 = q + (b_x / a_x)[..., None] * v_y + (b_y / a_y)[..., None] * v_x
    return np.stack(np.broadcast_arrays(h1, h2, h3), axis=-1)


def _unit(points: np.ndarray) -> np.ndarray:
    """Homogeneous points (K, 3) scaled to unit norm."""
    return points / np.maximum(np.linalg.norm(points, axis=1, keepdims=True), 1e-12)


def orthogonal_in_range(v_x: np.ndarray, v_y: np.ndarray, focal_lo_n: float, focal_hi_n: float,
                        max_cosine: float) -> np.ndarray:
    """(...) whether some focal length f_n in [focal_lo_n, focal_hi_n] (f / s) makes the directions of the
    vanishing points v_x and v_y ((..., 3), broadcast together; homogeneous, normalised coordinates) at most
    ``max_cosine`` from orthogonal: ``|cos(K^-1 v_x, K^-1 v_y)| <= max_cosine``.

    The cosine of a homography's first two axes (:func:`focal_and_mismatch`) is that of its vanishing points
    whatever the scale of each column, so a homography through a pair failing this is not a camera's: a necessary
    condition, decided for every pitch-line assignment of the pair at once. With ``g = 1 / f_n^2`` the condition is
    the quadratic ``(A g + B)^2 - c^2 (P1 g + z1^2)(P2 g + z2^2) <= 0``, asked at both ends of g's range and at its
    vertex.
    """
    x1, y1, z1 = (v_x[..., k] for k in range(3))
    x2, y2, z2 = (v_y[..., k] for k in range(3))
    A, B = x1 * x2 + y1 * y2, z1 * z2
    P1, P2, Q1, Q2 = x1 * x1 + y1 * y1, x2 * x2 + y2 * y2, z1 * z1, z2 * z2
    c2 = (max_cosine + 1e-6) ** 2  # a hair of slack: the boundary is kept whatever the rounding
    a2, a1, a0 = A * A - c2 * P1 * P2, 2 * A * B - c2 * (P1 * Q2 + P2 * Q1), B * B - c2 * Q1 * Q2
    g_lo, g_hi = 1.0 / focal_hi_n ** 2, 1.0 / focal_lo_n ** 2
    with np.errstate(divide="ignore", invalid="ignore"):
        vertex = np.clip(-a1 / (2 * a2), g_lo, g_hi)
    lowest = np.minimum(a2 * g_lo ** 2 + a1 * g_lo + a0, a2 * g_hi ** 2 + a1 * g_hi + a0)
    lowest = np.where((a2 > 0) & np.isfinite(vertex), np.minimum(lowest, a2 * vertex ** 2 + a1 * vertex + a0), lowest)
    return ~(lowest > 0)


def equal_norms_in_range(v_x: np.ndarray, v_y: np.ndarray, a_x: np.ndarray, a_y: np.ndarray, focal_lo_n: float,
                         focal_hi_n: float, max_mismatch: float) -> np.ndarray:
    """(B, Ma, Mb) whether some focal length f_n in [focal_lo_n, focal_hi_n] makes the axes ``K^-1 h1`` and
    ``K^-1 h2`` of each homography ``[-v_x / a_y, -v_y / a_x, ...]`` (:func:`homographies_from_maps`) of equal norm
    within ``max_mismatch`` (``| |a1| / |a2| - 1 |``, :func:`focal_and_mismatch`): a necessary condition of a
    camera's homography.

    Args:
        v_x, v_y: (B, 3) each pair of pairs' vanishing points (homogeneous, normalised coordinates, unit norm).
        a_x: (B, Ma) the slopes of the ``y = c`` family's maps; a_y: (B, Mb) the ``x = c`` family's.

    With ``g = 1 / f_n^2`` the ratio of norms is ``|a_x / a_y| rho(g)``, ``rho = sqrt((P1 g + z1^2) / (P2 g + z2^2))``
    (``P_i`` the squared x and y of a vanishing point), monotonic in g: its range is that of g's two ends.
    """
    P1 = v_x[:, 0] ** 2 + v_x[:, 1] ** 2
    P2 = v_y[:, 0] ** 2 + v_y[:, 1] ** 2
    g = np.array([1.0 / focal_hi_n ** 2, 1.0 / focal_lo_n ** 2])
    with np.errstate(divide="ignore", invalid="ignore"):
        rho = np.sqrt((P1[:, None] * g + v_x[:, 2:3] ** 2) / (P2[:, None] * g + v_y[:, 2:3] ** 2))  # (B, 2)
        rho_lo, rho_hi = rho.min(axis=1)[:, None, None], rho.max(axis=1)[:, None, None]
        ratio = np.abs(a_x)[:, :, None] / np.abs(a_y)[:, None, :]  # (B, Ma, Mb)
        slack = max_mismatch + 1e-6  # a hair of slack: the boundary is kept whatever the rounding
        return (ratio * rho_hi >= 1.0 - slack) & (ratio * rho_lo <= 1.0 + slack)


def focal_and_mismatch(H_n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """f / s of homographies (K, 3, 3) (normalised image coordinates) with the principal point at the image centre,
    and how far they are from a camera's: max(| |a1| / |a2| - 1 |, |cos(a1, a2)|) for ``a_i = K^-1 h_i`` (0 for the
    homography of a camera). f is NaN where the two conditions give no positive 1 / f^2.

    With ``K_n = diag(f_n, f_n, 1)``: ``a1 . a2 = 0`` and ``|a1| = |a2|`` each give ``1 / f_n^2`` linearly; the
    least-squares value of both is used (either alone can be degenerate, e.g. the orthogonality when a vanishing
    point is at infinity).
    """
    h1x, h1y, h1z = H_n[:, 0, 0], H_n[:, 1, 0], H_n[:, 2, 0]
    h2x, h2y, h2z = H_n[:, 0, 1], H_n[:, 1, 1], H_n[:, 2, 1]
    P1, P2 = h1x * h1x + h1y * h1y, h2x * h2x + h2y * h2y
    A1, B1 = h1x * h2x + h1y * h2y, h1z * h2z
    A2, B2 = P1 - P2, h1z * h1z - h2z * h2z
    with np.errstate(divide="ignore", invalid="ignore"):
        g = -(A1 * B1 + A2 * B2) / (A1 * A1 + A2 * A2)  # 1 / f_n^2
        focal_n = np.where(g > 0, 1.0 / np.sqrt(np.where(g > 0, g, 1.0)), np.nan)
        g = np.where(g > 0, g, np.nan)
        # |a_i|^2 and a1 . a2 with a_i = (h_ix / f, h_iy / f, h_iz).
        n1 = np.sqrt(P1 * g + h1z * h1z)
        n2 = np.sqrt(P2 * g + h2z * h2z)
        mismatch = np.maximum(np.abs(n1 / n2 - 1.0), np.abs(A1 * g + B1) / (n1 * n2))
    return focal_n, np.where(np.isfinite(mismatch), mismatch, np.inf)


def cameras_from_homographies(H_n: np.ndarray, frame_size, pitch: PitchTemplate,
                              config: CourtLineConfig = CourtLineConfig()) -> PlaneHypotheses:
    """The plausible broadcast cameras of ground-plane homographies (normalised image coordinates).

    f and the axes' mismatch: :func:`focal_and_mismatch`. Kept: f in range, the two axes
    orthogonal and of equal norm within ``max_axis_mismatch``, the focal point above the grass, off
    the playing area, within reach, a roll a broadcast camera has, and upright: the image's down
    direction points down in the world (``R_cw[1, 2] > 0``). An image turned half round shows a centre
    circle and the halfway line through it as they were, and its camera decomposes with roll 0 and
    the tilt negated: the roll alone does not tell it.

    Args:
        H_n: (K, 3, 3) homographies, pitch (x, y, 1) metres -> normalised image points.
    """
    return plausible_cameras(H_n, frame_size, pitch, config)[0]


def plausible_cameras(H_n: np.ndarray, frame_size, pitch: PitchTemplate, config: CourtLineConfig = CourtLineConfig()
                      ) -> tuple[PlaneHypotheses, np.ndarray]:
    """:func:`cameras_from_homographies`, with the indices into ``H_n`` of the homographies kept."""
    H_n = np.asarray(H_n, float).reshape(-1, 3, 3)
    index = np.arange(len(H_n))
    focal_n, mismatch = focal_and_mismatch(H_n)
    f_lo, f_hi = (2.0 * v for v in config.focal_range_per_width)  # f / s = 2 f / W
    keep = np.isfinite(focal_n) & (focal_n >= f_lo) & (focal_n <= f_hi) & (mismatch <= config.max_axis_mismatch)
    H_n, focal_n, index = H_n[keep], focal_n[keep], index[keep]
    # The sign making the ground point seen at the image centre lie in front: H^-1 e3 ~ (.., .., (h1 x h2)_z / det H),
    # det H the triple product h1 x h2 . h3. A homography of determinant 0 (its horizon through the image centre) is
    # no camera's: not kept.
    h12 = cross3(H_n[:, :, 0], H_n[:, :, 1])
    sign = np.sign(h12[:, 2]) * np.sign(np.einsum("ki,ki->k", h12, H_n[:, :, 2]))
    proper = np.isfinite(sign) & (sign != 0)
    H_n, focal_n, index, sign = H_n[proper], focal_n[proper], index[proper], sign[proper]
    scale_k = np.stack([1.0 / focal_n, 1.0 / focal_n, np.ones_like(focal_n)], axis=1)[:, :, None]
    a = H_n * scale_k  # columns a1, a2, a3
    n1, n2 = np.linalg.norm(a[:, :, 0], axis=1), np.linalg.norm(a[:, :, 1], axis=1)
    scale = np.sqrt(n1 * n2)
    r1 = sign[:, None] * a[:, :, 0] / n1[:, None]
    r2 = sign[:, None] * a[:, :, 1] / n2[:, None]
    # The two axes made orthonormal symmetrically (about their bisector), the third their cross product.
    bisector = r1 + r2
    bisector /= np.linalg.norm(bisector, axis=1, keepdims=True)
    across = r1 - r2
    across /= np.linalg.norm(across, axis=1, keepdims=True)
    r1, r2 = (bisector + across) / math.sqrt(2.0), (bisector - across) / math.sqrt(2.0)
    R = np.stack([r1, r2, cross3(r1, r2)], axis=2)
    t = sign[:, None] * a[:, :, 2] / scale[:, None]
    C = -np.einsum("kji,kj->ki", R, t)
    half_l, half_w = pitch.dimensions.length_m / 2, pitch.dimensions.width_m / 2
    margin = -config.inside_pitch_slack_m
    height = -C[:, 2]
    placed = np.nonzero((sign != 0) & (height >= config.height_range_m[0]) & (height <= config.height_range_m[1])
                        & (np.hypot(C[:, 0], C[:, 1]) <= config.max_distance_m)
                        & ((np.abs(C[:, 0]) >= half_l + margin) | (np.abs(C[:, 1]) >= half_w + margin))
                        & (R[:, 1, 2] > 0) & np.all(np.isfinite(R), axis=(1, 2)))[0]
    angles = angles_from_rotations(R[placed]) if len(placed) else np.zeros((0, 3))  # of the cameras placed only
    level = np.abs(angles[:, 2]) <= math.radians(config.max_roll_deg)
    keep = placed[level]
    return (PlaneHypotheses(H_n[keep], focal_n[keep], R[keep], C[keep], angles[level], sign[keep], scale[keep]),
            index[keep])


def concatenate(parts: list[PlaneHypotheses]) -> PlaneHypotheses:
    """The hypotheses of several parts as one set (an empty set when there are none)."""
    if not parts:
        return PlaneHypotheses(np.zeros((0, 3, 3)), np.zeros(0), np.zeros((0, 3, 3)), np.zeros((0, 3)),
                               np.zeros((0, 3)), np.zeros(0), np.zeros(0))
    return PlaneHypotheses(*(np.concatenate([getattr(p, name) for p in parts])
                             for name in PlaneHypotheses.__dataclass_fields__))


def pixel_homographies(hypotheses: PlaneHypotheses, frame_size) -> np.ndarray:
    """(K, 3, 3) the hypotheses' homographies to frame pixels (the normalisation undone)."""
    W, H = frame_size
    to_px = np.array([[W / 2.0, 0.0, W / 2.0], [0.0, W / 2.0, H / 2.0], [0.0, 0.0, 1.0]])
    return to_px[None] @ hypotheses.H_n
