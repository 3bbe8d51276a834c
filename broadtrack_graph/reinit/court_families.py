"""The image's straight markings split into the pitch's two directions by where they meet. No I/O.

The pitch's straight markings run in two directions (parallel to the touchlines and to the goal lines); in the
image the lines of each meet at a vanishing point. A line is solid when the map draws it along most of its extent
where no player stands on it (:func:`hidden_lengths_px`). Every intersection of two solid image lines is a candidate,
unless it lies inside either line's extent (painted lines crossing there are not parallel on the grass: a corner),
voted for by the support of the lines pointing at it (:func:`vanishing_votes`); the pairs of candidates that take
the most of the lines' support, and that a focal length in range can make orthogonal, split the lines into two
families (:func:`line_families`), from which :mod:`broadtrack_graph.reinit.court_lines` forms its homographies.

Image coordinates are normalised as in :mod:`broadtrack_graph.reinit.court_lines`: ``x_n = (u - W / 2) / s``,
``y_n = (v - H / 2) / s`` with ``s = W / 2``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.detect.marking_structures import HatchRule, ImageLine, hatched
from broadtrack_graph.geometry.matrices import cross3


@dataclass(frozen=True)
class CourtLineConfig:
    """Settings of the line-family hypotheses (angles in degrees, pixels at the frame size unless stated)."""

    max_lines_per_family: int = 4  # the best supported image lines of each family are paired
    family_angle_px: float = 2.5  # a line joins a vanishing point when its far end is within this of the ray
    family_angle_min_deg: float = 0.3  # ... an angle tolerance never tighter than this ...
    family_angle_max_deg: float = 2.5  # ... nor looser than this
    # map pixels per pixel of a line's extent, at least (a painted marking is drawn along)
    min_line_coverage: float = 0.45
    hatch: HatchRule = HatchRule()  # the lines of a hatch (a goal net's strands) join no family
    # Two lines meeting inside either's extent (clear of its ends by this share of its length) cross on the grass:
    # they are not parallel there, and their meeting point is a corner, not a candidate vanishing point
    crossing_inside_share: float = 0.05
    # Two vanishing points both this near the image (|w| of the unit homogeneous point: within about 1 / w half
    # widths of the centre) must fit a focal length in range (within a factor 2: a far one is poorly placed)
    near_vanishing_w: float = 0.15
    # The pairs of candidate vanishing points are ranked by the support of the lines either takes (the split that
    # explains the most of the straight markings first); the best max_splits distinct pairs are kept ...
    max_splits: int = 16
    vanishing_pool: int = 64  # ... of the pairs among this many best voted distinct candidates (bounded time)
    focal_range_per_width: tuple[float, float] = (0.45, 16.0)  # f / W accepted (fields of view about 126 to 3.6 deg)
    max_axis_mismatch: float = 0.3  # |K^-1 h1| / |K^-1 h2| - 1 and the cosine between them, at most
    height_range_m: tuple[float, float] = (2.0, 150.0)  # focal point above the grass
    max_distance_m: float = 250.0  # focal point within this horizontal distance of the centre spot
    max_roll_deg: float = 10.0  # |roll| of a broadcast camera
    # A hypothesis's focal point stands off the playing area, or at most this far inside it: decomposed from a few
    # markings (an arc's conic, a short line), it is metres off; the fitted camera must stand off it (reinit.frame.
    # plausible_position).
    inside_pitch_slack_m: float = 5.0


@dataclass(frozen=True)
class LineFamilies:
    """The image lines split into the pitch's two directions.

    lines_n: (L, 3) every image line, normalised coordinates, ``a^2 + b^2 = 1``.
    family: (L,) 0 or 1 for the family a line joined, -1 for none.
    vanishing_n: (2, 3) the families' vanishing points (homogeneous, unit norm); rows of a family with
        fewer than two lines are NaN.
    scale_px: s of the normalisation; centre_px: (2,) the image centre.
    """

    lines_n: np.ndarray
    family: np.ndarray
    vanishing_n: np.ndarray
    scale_px: float
    centre_px: np.ndarray

    def members(self, k: int, max_lines: int, support_px: np.ndarray) -> np.ndarray:
        """Indices of family k's lines, the best supported ``max_lines`` of them."""
        own = np.nonzero(self.family == k)[0]
        return own[np.argsort(-support_px[own])][:max_lines]


def normalised_lines(lines: list[ImageLine], frame_size: tuple[int, int]) -> tuple[np.ndarray, float, np.ndarray]:
    """(L, 3) the lines ``n . p + o = 0`` (frame pixels) in normalised coordinates, with s and the image centre."""
    W, H = frame_size
    s, centre = W / 2.0, np.array([W / 2.0, H / 2.0])
    if not lines:
        return np.zeros((0, 3)), s, centre
    normals = np.array([line.normal for line in lines], float)
    offsets = np.array([line.offset_px for line in lines], float)
    out = np.column_stack([normals * s, normals @ centre + offsets])
    return out / np.linalg.norm(out[:, :2], axis=1, keepdims=True), s, centre


def _meets(lines_n: np.ndarray, centres_n: np.ndarray, tolerances: np.ndarray, points: np.ndarray) -> np.ndarray:
    """(P, L) whether each line points at each homogeneous point (P, 3), within its angle tolerance (L,) radians."""
    to_point = points[:, None, :2] - centres_n[None, :, :] * points[:, None, 2:3]  # (P, L, 2), valid at infinity
    norm = np.linalg.norm(to_point, axis=2)
    along = np.stack([-lines_n[:, 1], lines_n[:, 0]], axis=1)  # line directions (L, 2)
    sine = np.abs(to_point[..., 0] * along[None, :, 1] - to_point[..., 1] * along[None, :, 0]) / np.maximum(norm, 1e-12)
    return sine < np.sin(tolerances)[None, :]


def _crossing(lines: list[ImageLine], points_n: np.ndarray, i: np.ndarray, j: np.ndarray, s: float,
              centre_px: np.ndarray, inside_share: float) -> np.ndarray:
    """(P,) whether each meeting point (homogeneous, normalised coordinates) of lines i and j lies inside the extent
    of line i or of line j, clear of its ends by ``inside_share`` of its length: painted lines crossing there."""
    w = points_n[:, 2]
    finite = np.abs(w) > 1e-9
    point_px = points_n[:, :2] / np.where(finite, w, 1.0)[:, None] * s + centre_px
    centres = np.array([line.centre_px for line in lines])
    directions = np.array([line.direction for line in lines])
    extents = np.array([line.extent_px for line in lines], float)
    margins = inside_share * (extents[:, 1] - extents[:, 0])

    def inside(k: np.ndarray) -> np.ndarray:
        along = np.einsum("pk,pk->p", point_px - centres[k], directions[k])
        return (along > extents[k, 0] + margins[k]) & (along < extents[k, 1] - margins[k])

    return finite & (inside(i) | inside(j))


@dataclass(frozen=True)
class VanishingVotes:
    """Every intersection of two solid image lines as a candidate vanishing point, with the lines pointing at it.

    lines_n: (L, 3) the lines, normalised coordinates; scale_px, centre_px: the normalisation; support_px: (L,);
    solid: (L,) the lines that may join a direction (drawn along, not a hatch's); i, j: (P,) the two lines of each
    point; meets: (P, L) the solid lines pointing at each point.
    """

    lines_n: np.ndarray
    scale_px: float
    centre_px: np.ndarray
    support_px: np.ndarray
    solid: np.ndarray
    i: np.ndarray
    j: np.ndarray
    meets: np.ndarray


def hidden_lengths_px(lines: list[ImageLine], player_mask: np.ndarray | None, frame_width_px: int) -> np.ndarray:
    """(L,) frame pixels of each line's extent that the players hide: a painted line is drawn along its extent
    except where a player stands on it (the map holds no marking there). Zeros without a player mask.

    Args:
        player_mask: (h, w) bool (or non-zero where a player stands), any size of the frame's aspect ratio.
    """
    if player_mask is None or not lines or not player_mask.any():
        return np.zeros(len(lines))
    h, w = player_mask.shape
    to_mask = w / float(frame_width_px)
    out = np.zeros(len(lines))
    for k, line in enumerate(lines):
        lo, hi = line.extent_px
        along = np.arange(lo, hi, max(1.0 / to_mask, 1.0))  # about one mask pixel a step
        if not len(along):
            continue
        uv = (line.centre_px + along[:, None] * line.direction) * to_mask
        cols, rows = np.clip(uv[:, 0].astype(int), 0, w - 1), np.clip(uv[:, 1].astype(int), 0, h - 1)
        out[k] = (hi - lo) * float(np.mean(player_mask[rows, cols] != 0))
    return out


def vanishing_votes(lines: list[ImageLine], frame_size: tuple[int, int],
                    config: CourtLineConfig = CourtLineConfig(), hidden_px: np.ndarray | None = None
                    ) -> VanishingVotes | None:
    """The candidate vanishing points of the lines (:class:`VanishingVotes`); None under two solid lines.
    ``hidden_px``: (L,) the length of each line's extent the players hide (:func:`hidden_lengths_px`), not asked
    to be drawn (at most half of it)."""
    lines_n, s, centre = normalised_lines(lines, frame_size)
    if len(lines_n) < 2:
        return None
    centres_n = (np.array([line.centre_px for line in lines]) - centre) / s
    lengths_px = np.array([max(line.extent_px[1] - line.extent_px[0], 1.0) for line in lines])
    shown_px = lengths_px if hidden_px is None else np.maximum(lengths_px - hidden_px, 0.5 * lengths_px)
    support = np.array([line.support_px for line in lines])
    crowded = hatched(lines, frame_size[0], config.hatch)
    solid = (support >= config.min_line_coverage * shown_px) & ~crowded
    tolerances = np.clip(np.arctan(config.family_angle_px / (0.5 * lengths_px)),
                         math.radians(config.family_angle_min_deg), math.radians(config.family_angle_max_deg))
    i, j = np.triu_indices(len(lines_n), 1)
    pair_ok = solid[i] & solid[j]
    i, j = i[pair_ok], j[pair_ok]
    if not len(i):
        return None
    points = cross3(lines_n[i], lines_n[j])
    points /= np.maximum(np.linalg.norm(points, axis=1, keepdims=True), 1e-12)
    apart = ~_crossing(lines, points, i, j, s, centre, config.crossing_inside_share)
    i, j, points = i[apart], j[apart], points[apart]
    if not len(i):
        return None
    meets = _meets(lines_n, centres_n, tolerances, points) & solid[None, :]
    return VanishingVotes(lines_n, s, centre, support, solid, i, j, meets)


def line_families(lines: list[ImageLine], frame_size: tuple[int, int],
                  config: CourtLineConfig = CourtLineConfig(), hidden_px: np.ndarray | None = None
                  ) -> list[LineFamilies]:
    """Ways of splitting the image lines into the pitch's two directions, likeliest first.

    Every intersection of two lines is a candidate vanishing point, voted for by the support (map pixels) of the
    lines pointing at it; the ``vanishing_pool`` best voted candidates with distinct line sets are paired. A pair
    splits the lines: the better voted point's lines are the first family, the other point's lines left the second
    (at least two each). The pairs are ranked by the support of the lines the split takes, and the best
    ``max_splits`` are kept that differ from every split kept before (either family sharing at most half its
    lines with its counterpart's) and whose two directions can be orthogonal for some focal length in range (two
    finite vanishing points v1, v2 of orthogonal directions satisfy ``v1 . v2 = -f^2`` about the image centre).
    Ranked on the split, not on each point: every point on the longest line outvotes any point of two shorter
    lines, so points ranked alone pair the longest line with each of the next longest, whatever their direction,
    and a short line of the longest one's direction is left out. Each family's vanishing point is the
    least-squares meeting point of its lines. A goal net's strands or a board's edges make vanishing points of
    their own: the best splits are all kept, and the map decides.
    Lines drawn along less than ``min_line_coverage`` of their extent where no player hides it (``hidden_px``,
    :func:`vanishing_votes`; a Hough line through scattered specks) and lines of a hatch
    (:func:`~broadtrack_graph.detect.marking_structures.hatched`: a goal net's strands) join no family.
    """
    votes = vanishing_votes(lines, frame_size, config, hidden_px)
    if votes is None or len(votes.lines_n) < 4:
        return []
    lines_n, s, centre, support, meets = votes.lines_n, votes.scale_px, votes.centre_px, votes.support_px, votes.meets
    order = np.argsort(-(meets @ support), kind="stable")
    order = order[meets[order].sum(axis=1) >= 2]
    _, first_of_set = np.unique(meets[order], axis=0, return_index=True)
    pool = meets[order[np.sort(first_of_set)][:config.vanishing_pool]]  # (Q, L), best voted first
    a, b = np.triu_indices(len(pool), 1)
    second = pool[b] & ~pool[a]  # the lines the better voted point leaves to the other
    two = second.sum(axis=1) >= 2
    splits = np.stack([pool[a[two]], second[two]], axis=1)  # (S, 2, L): the first family's lines, the second's
    if not len(splits):
        return []
    _, first_of_split = np.unique(np.packbits(splits.reshape(len(splits), -1), axis=1), axis=0, return_index=True)
    splits = splits[np.sort(first_of_split)]  # each split once
    splits = splits[np.argsort(-(splits.any(axis=1) @ support), kind="stable")]
    sizes = splits.sum(axis=2)  # (S, 2)
    f_lo, f_hi = (2.0 * v for v in config.focal_range_per_width)
    out: list[LineFamilies] = []
    kept = np.zeros((config.max_splits, 2, len(lines_n)), int)
    kept_sizes = np.ones((config.max_splits, 2))
    for sets, size in zip(splits, sizes):
        shared = np.einsum("kfl,fl->kf", kept[:len(out)], sets)
        if np.any(np.all(shared > 0.5 * np.minimum(kept_sizes[:len(out)], size), axis=1)):
            continue  # both families as a split's kept before, but for a line or so
        vanishing = np.stack([np.linalg.svd(lines_n[members])[2][-1] for members in sets])
        w1, w2 = vanishing[:, 2]
        if min(abs(w1), abs(w2)) > config.near_vanishing_w:  # both near the image: the orthogonality gives f
            f2 = -(vanishing[0, :2] @ vanishing[1, :2]) / (w1 * w2)
            if not (f_lo / 2) ** 2 <= f2 <= (2 * f_hi) ** 2:
                continue
        family = np.full(len(lines_n), -1)
        family[sets[0]], family[sets[1]] = 0, 1
        kept[len(out)], kept_sizes[len(out)] = sets, size
        out.append(LineFamilies(lines_n, family, vanishing, s, centre))
        if len(out) >= config.max_splits:
            break
    return out


def distinct_sets(meets: np.ndarray, votes: np.ndarray, count: int) -> list[np.ndarray]:
    """Up to ``count`` line sets (rows of meets, (P, L) bool) of at least two lines, best voted first, each sharing
    at most half its lines with a set taken before it."""
    taken: list[np.ndarray] = []
    for k in np.argsort(-votes):
        members = meets[k]
        if votes[k] < 0 or members.sum() < 2:
            break
        if all(np.sum(members & other) <= 0.5 * min(members.sum(), other.sum()) for other in taken):
            taken.append(members)
            if len(taken) >= count:
                break
    return taken
