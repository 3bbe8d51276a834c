"""The weight-free detector's marking ridges: thin bright lines on grass, to sub-pixel centre-line points. No I/O.

A white top-hat of the working image's marking channel (:func:`marking_channel`) keeps structures up to about the
kernel's width brighter than their surroundings; its pixels above a threshold (a fixed level, or above the level the
grass texture reaches on the frame) where markings may be are the candidates; on a blurred frame, whose markings are
smeared to a fraction of their contrast, the pixels over a lower level (``faint_threshold``, or the grass texture's)
8-connected to them join them (hysteresis: a faint stretch of line is followed from its brighter ones; texture under
the threshold joins only where it touches a candidate; of its points, those more colourful than the ground around
them are then dropped, :func:`white`: the coloured lines of other sports on artificial turf are followed as well).
Each candidate is moved to the sub-pixel centre of its ridge with Steger's method: the Hessian of the smoothed
top-hat gives the direction across the line (its most negative eigenvalue's eigenvector) and the offset along it; a
candidate whose centre lies within half a pixel, on a ridge curved enough, and with enough other centre-line points
around it (a marking is long, a speck of texture is not) is kept. Derivatives are taken at the candidate pixels
only.

Markings wider than the Hessian's scale or the top-hat's kernel (a zoomed view, the near lines of a low camera)
have a flat top there: the points found lie off the centre or on the line's edges, and past about 12 px there
are none. :func:`wide_ridges` runs the same steps again on the grey image reduced 2x and 4x (``wide_levels``; the
same kernels in the reduced pixels, where such a line is narrow again), each level's points mapped back to working
pixels. A stretch of line belongs to the finest level that finds it as a peaked ridge (curvature across over
height at least ``wide_min_peak``): a coarser level looks only at its pixels that hold no finer peaked point. There
a wide line is resolved, so its paint shows at full contrast (the threshold is ``wide_threshold_factor`` times the
level's) and rises and falls in steps at its edges (the steepest one-pixel step on each side at least
``wide_edge_share`` of its height: a mown stripe or a soft band of light brightens over many pixels); the finer
points across such a line within its stretch (its edges, its flat top) give way to its own. The detector asks for
it when the predicted camera draws a marking that wide, and at once on a blurred frame, whose markings are all smeared
wide and faint (:func:`wide_points`: both gates eased by the frame's blur).
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import cv2
import numpy as np

from broadtrack_graph.detect.image_reads import read_at
from broadtrack_graph.detect.point_cells import pixels_of
from broadtrack_graph.detect.ridge_sides import grass_beside
from broadtrack_graph.geometry.point_pairs import pairs_within


def _reflect_101(index: np.ndarray, size: int) -> np.ndarray:
    """Indices in [-1, size] mapped into [0, size) as OpenCV's BORDER_REFLECT_101 pads (-1 -> 1, size -> size - 2)."""
    return (size - 1) - np.abs((size - 1) - np.abs(index)) if size > 1 else np.zeros_like(index)


def marking_ridges(grey: np.ndarray, allowed: np.ndarray, grass: np.ndarray | None, tophat_kernel: np.ndarray,
                   ridge_kernel: np.ndarray, c, follow_faint: bool = False, sides: np.ndarray | None = None
                   ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Sub-pixel centre-line points (N, 2) (working pixels), whether each lies on a peaked ridge (N,) bool (a line
    the Hessian's scale resolves; module docstring) and the candidate map (uint8) (module docstring).

    Args:
        grey: (h, w) uint8 grey working image (already pre-smoothed as needed).
        allowed: (h, w) uint8, non-zero where markings may be.
        grass: (h, w) uint8 grass mask, or None; the threshold adapts to the top-hat of grass texture and noise there.
        tophat_kernel: the top-hat's structuring element (``tophat_kernel_px`` square).
        ridge_kernel: the 1-D float32 Gaussian of the Hessian's scale (``ridge_sigma_px``), applied along both axes.
        c: the detector's settings (:class:`~broadtrack_graph.detect.weightfree_config.WeightFreeConfig`: its threshold,
            support, curvature and wide-marking fields).
        follow_faint: join to the candidates the pixels over the weak level (``faint_threshold``, or the grass
            texture's) 8-connected to them (hysteresis; a blurred frame's: its markings are smeared to a fraction of
            their contrast, their faint stretches followed from the bright ones).
        sides: (h, w) uint8 grass mask, or None: the points kept only with grass on both sides past their ridge's
            edges (``side_margin_px``, :func:`~broadtrack_graph.detect.ridge_sides.grass_beside`).
    """
    tophat = cv2.morphologyEx(grey, cv2.MORPH_TOPHAT, tophat_kernel)
    allowed01 = cv2.threshold(allowed, 0, 1, cv2.THRESH_BINARY)[1]
    weak = _threshold(tophat, grass, c, c.faint_threshold) if follow_faint else None
    points, peak, normals, candidates = _centre_points(tophat, allowed01, _threshold(tophat, grass, c), ridge_kernel,
                                                       c, weak)
    if sides is not None and c.side_margin_px > 0:  # paint lies on grass (detect.ridge_sides)
        on_grass = grass_beside(points, normals, candidates, sides, c.side_margin_px)
        points, peak = points[on_grass], peak[on_grass]
    return points, peak >= c.wide_min_peak, candidates


def ridge_points_at(tophat: np.ndarray, allowed01: np.ndarray, level: float, ridge_kernel: np.ndarray, c
                    ) -> tuple[np.ndarray, np.ndarray]:
    """The centre-line points (N, 2) of the top-hat's ridges over ``level`` where ``allowed01`` is 1, kept on curvature
    and support as :func:`marking_ridges` keeps its own, and their unit normals (N, 2) (across the ridge). Pixels of
    the top-hat's image."""
    points, _, normals, _ = _centre_points(tophat, allowed01, level, ridge_kernel, c)
    return points, normals


def white(colour_bgr: np.ndarray, points: np.ndarray, max_rise: float, window_px: int = 15) -> np.ndarray:
    """(N,) bool: the points no more colourful than the ground around them: the image's chroma (the largest channel
    less the smallest, grey levels) at each point (bilinear, at its sub-pixel place) at most ``max_rise`` over its mean
    in the ``window_px`` square there. White paint mixed into grass takes colour away, whatever its share of the
    pixel; the coloured lines of other sports on artificial turf (yellow, orange, red, light blue) add it.

    Args:
        colour_bgr: (h, w, 3) uint8 image; points: (N, 2) pixels of it.
    """
    if not len(points):
        return np.zeros(0, bool)
    b, g, r = cv2.split(colour_bgr)
    chroma = cv2.subtract(cv2.max(cv2.max(b, g), r), cv2.min(cv2.min(b, g), r)).astype(np.float32)
    around = cv2.blur(chroma, (window_px, window_px))
    xs, ys = points[:, 0].astype(np.float32), points[:, 1].astype(np.float32)
    return read_at(chroma, xs, ys) - read_at(around, xs, ys) <= max_rise


def wide_ridges(grey: np.ndarray, wide_allowed: np.ndarray, grass: np.ndarray | None, points: np.ndarray,
                peaked: np.ndarray, tophat_kernel: np.ndarray, ridge_kernel: np.ndarray, c) -> np.ndarray:
    """The working level's points with the wide markings' found on the reduced levels (module docstring): (M, 2)
    working pixels, the working level's first (those across a wide line dropped), then each coarser level's.

    Args:
        grey, grass, tophat_kernel, ridge_kernel, c: as :func:`marking_ridges`.
        wide_allowed: (h, w) uint8, non-zero where wide markings may be (a wide marking's middle lies farther from
            grass than a thin one's).
        points, peaked: :func:`marking_ridges`'s points and peaked flags.
    """
    h, w = grey.shape
    level_grey, level_grass = grey, grass
    level_allowed = cv2.threshold(wide_allowed, 0, 1, cv2.THRESH_BINARY)[1]
    kept, peaked = np.asarray(points, float).reshape(-1, 2), np.asarray(peaked, bool)
    kept_px = pixels_of(kept, (w, h))
    taken = np.zeros((h, w), np.uint8)  # the pixels holding a peaked point (at the last level's size)
    taken[kept_px[peaked, 1], kept_px[peaked, 0]] = 1
    for level in range(1, c.wide_levels + 1):
        scale = 2 ** level
        size = (level_grey.shape[1] // 2, level_grey.shape[0] // 2)
        if min(size) < 2 * tophat_kernel.shape[0]:
            break
        rows, cols = 2 * size[1], 2 * size[0]
        level_grey = cv2.resize(level_grey[:rows, :cols], size, interpolation=cv2.INTER_AREA)
        # A coarse pixel may hold a marking only where all four of its finer pixels may, and a stretch of line the
        # finer levels found at their own scale (a coarse pixel holding a peaked ridge point of theirs) is theirs:
        # only the others are wide lines' candidates.
        level_allowed, taken = (cv2.morphologyEx(image[:rows, :cols], op, np.ones((2, 2), np.uint8),
                                                 anchor=(0, 0))[::2, ::2]
                                for image, op in ((level_allowed, cv2.MORPH_ERODE), (taken, cv2.MORPH_DILATE)))
        level_grass = None if level_grass is None else level_grass[:rows:2, :cols:2]
        # The top-hat's border is the image's edge, not grass: a reduced level keeps to its inside.
        margin = tophat_kernel.shape[0] // 2
        free = np.zeros_like(level_allowed)
        free[margin:-margin, margin:-margin] = level_allowed[margin:-margin, margin:-margin]
        free[taken > 0] = 0
        tophat = cv2.morphologyEx(level_grey, cv2.MORPH_TOPHAT, tophat_kernel)
        threshold = _threshold(tophat, level_grass, c) * c.wide_threshold_factor
        found, peak, normals, _ = _centre_points(tophat, free, threshold, ridge_kernel, c)
        found = found * scale + (scale - 1) / 2.0  # a level's pixel centre in working pixels
        # A wide line is paint if it has paint's sharp edges; the finer points across it (its edges, its flat top)
        # give way to its own.
        edge_px = (scale // 2) * (tophat_kernel.shape[0] // 2 + 1)
        paint = _sharp_edged(grey, found, normals, 2 * edge_px, c.wide_edge_share)
        found, peak, normals = found[paint], peak[paint], normals[paint]
        found_px = pixels_of(found, (w, h))
        beside = _across(kept, kept_px // scale, found, found_px // scale, normals, edge_px, scale / 2.0 + 0.5, scale,
                         free.shape)
        if beside.any():
            kept, kept_px, peaked = kept[~beside], kept_px[~beside], peaked[~beside]
        peak = peak >= c.wide_min_peak
        taken[found_px[peak, 1] // scale, found_px[peak, 0] // scale] = 1
        kept, kept_px, peaked = np.vstack([kept, found]), np.vstack([kept_px, found_px]), np.concatenate([peaked, peak])
    return kept


@dataclass(frozen=True)
class WideInputs:
    """What :func:`wide_ridges` needs of a frame, kept from its working level: the grey working image, the field's
    filled outline without players, the ridges' inner field, the grass mask, the grass the threshold adapts to (or
    None) and the working level's peaked flags."""

    grey: np.ndarray
    outline: np.ndarray
    inner: np.ndarray
    grass: np.ndarray
    threshold_grass: np.ndarray | None
    peaked: np.ndarray


def wide_points(wide: WideInputs, points: np.ndarray, reach_kernel: np.ndarray, tophat_kernel: np.ndarray,
                ridge_kernel: np.ndarray, c, blur: float = 1.0) -> np.ndarray:
    """:func:`wide_ridges` of a frame: its working level's ``points`` (N, 2) with its wide markings' (M, 2), where the
    field lies within ``reach_kernel`` of grass (a wide marking's middle lies farther from it than a thin one's). A
    frame blurred ``blur`` times a sharp frame's edge width (:mod:`~broadtrack_graph.detect.sharpness`) shows its
    paint's edges that much softer and its contrast spread: the edge share and the threshold factor (``c``'s
    ``wide_edge_share``, ``wide_threshold_factor``, at least 1) are divided by it."""
    if blur > 1.0:
        c = replace(c, wide_edge_share=c.wide_edge_share / blur,
                    wide_threshold_factor=max(1.0, c.wide_threshold_factor / blur))
    allowed = cv2.bitwise_and(cv2.bitwise_and(wide.outline, cv2.dilate(wide.grass, reach_kernel)), wide.inner)
    return wide_ridges(wide.grey, allowed, wide.threshold_grass, points, wide.peaked, tophat_kernel, ridge_kernel, c)


def _across(points: np.ndarray, cells: np.ndarray, centres: np.ndarray, centre_cells: np.ndarray, normals: np.ndarray,
            across_px: float, along_px: float, scale: int, level_shape: tuple[int, int]) -> np.ndarray:
    """(N,) bool: each point (working pixels) within across_px of a centre-line point across its line (along its unit
    normal) and within along_px along it (that centre's own stretch of line, not its neighbours'). The points near a
    centre are picked first on the centres' level (``cells``, ``centre_cells``: the (col, row) pixels there of the
    points and of the centres; scale: working pixels per level pixel; level_shape: its (h, w)), then tested
    exactly."""
    out = np.zeros(len(points), bool)
    if not len(points) or not len(centres):
        return out
    reach = float(np.hypot(across_px, along_px))
    near = np.zeros(level_shape, np.uint8)
    near[np.minimum(centre_cells[:, 1], level_shape[0] - 1), np.minimum(centre_cells[:, 0], level_shape[1] - 1)] = 1
    reach_cells = int(np.ceil(reach / scale)) + 1
    near = cv2.dilate(near, np.ones((2 * reach_cells + 1, 2 * reach_cells + 1), np.uint8))
    close = np.flatnonzero(near[np.minimum(cells[:, 1], level_shape[0] - 1), np.minimum(cells[:, 0], level_shape[1] - 1)])
    if not len(close):
        return out
    centre, point = pairs_within(centres, points[close], reach)
    point = close[point]
    offset = points[point] - centres[centre]
    across = np.abs(np.sum(offset * normals[centre], axis=1))
    along = np.abs(offset[:, 0] * normals[centre, 1] - offset[:, 1] * normals[centre, 0])
    out[point[(across <= across_px) & (along <= along_px)]] = True
    return out


def _sharp_edged(grey: np.ndarray, points: np.ndarray, normals: np.ndarray, reach_px: int, share: float
                 ) -> np.ndarray:
    """(N,) bool: the working grey image across each point's line (along its normal, reach_px each way) rises to it
    and falls from it in a step: its steepest one-pixel rise before the point and fall after it are each at least
    ``share`` of the profile's height. Paint has sharp edges at any width; a mown stripe or a soft shadow edge
    brightens over many pixels."""
    if not len(points):
        return np.zeros(0, bool)
    steps = np.arange(-reach_px, reach_px + 1, dtype=np.float32)
    xs = (points[:, 0, None] + steps * normals[:, 0, None]).astype(np.float32)
    ys = (points[:, 1, None] + steps * normals[:, 1, None]).astype(np.float32)
    profile = read_at(grey, xs, ys).astype(np.float32)
    height = profile[:, reach_px - 1:reach_px + 2].max(axis=1) - profile.min(axis=1)
    rise = np.diff(profile[:, :reach_px + 1], axis=1).max(axis=1)
    fall = -np.diff(profile[:, reach_px:], axis=1).min(axis=1)
    return (height > 0) & (rise >= share * height) & (fall >= share * height)


def _threshold(tophat: np.ndarray, grass: np.ndarray | None, c, floor: float | None = None) -> float:
    """The top-hat's threshold: ``floor`` (``tophat_threshold`` when None), raised above the level grass texture
    reaches when a grass map is given (its 90th percentile there plus ``tophat_noise_margin``; the grass of the field,
    where markings may be)."""
    threshold = c.tophat_threshold if floor is None else floor
    if grass is not None:
        sample = tophat[::4, ::4][grass[::4, ::4] > 0]  # markings are a few per cent of the grass
        if len(sample) > 100:
            threshold = max(threshold, float(np.percentile(sample, 90)) + c.tophat_noise_margin)
    return threshold


def _hysteresis(strong01: np.ndarray, weak01: np.ndarray) -> np.ndarray:
    """(h, w) uint8 0/1: the pixels of ``weak01`` (which holds ``strong01``) 8-connected to a pixel of ``strong01``."""
    count, labels = cv2.connectedComponents(weak01, connectivity=8)
    reached = np.zeros(count, np.uint8)
    reached[labels[strong01 > 0]] = 1
    reached[0] = 0
    return reached[labels]


def _centre_points(tophat: np.ndarray, allowed01: np.ndarray, threshold: float, ridge_kernel: np.ndarray, c,
                   weak_threshold: float | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """One level's centre-line points (N, 2) (its pixels), their peakedness (N,), unit normals (N, 2) (across the
    line) and the candidate map: the top-hat's pixels over the threshold where allowed01 is 1, moved to their
    ridge's centre and kept on curvature and support (module docstring). Peakedness: the curvature across the
    ridge over its height (1 / px^2; a line wider than the Hessian's scale has a flat top, under ``wide_min_peak``).
    """
    candidates = cv2.bitwise_and(cv2.threshold(tophat, threshold, 1, cv2.THRESH_BINARY)[1], allowed01)
    if weak_threshold is not None and weak_threshold < threshold:  # hysteresis (marking_ridges' follow_faint)
        candidates = _hysteresis(candidates, cv2.bitwise_and(
            cv2.threshold(tophat, weak_threshold, 1, cv2.THRESH_BINARY)[1], allowed01))
    found = cv2.findNonZero(candidates)
    if found is None:
        return np.zeros((0, 2)), np.zeros(0), np.zeros((0, 2)), candidates
    found = found.reshape(-1, 2)
    xs, ys = found[:, 0], found[:, 1]
    h, w = tophat.shape
    # GaussianBlur's own float kernel and border, filtered straight from the uint8 top-hat (the same numbers
    # without converting the image first).
    smooth = cv2.sepFilter2D(tophat, cv2.CV_32F, ridge_kernel, ridge_kernel)
    flat = smooth.ravel()
    # The 3x3 neighbours' flat indices, reflected at the image border as BORDER_REFLECT_101 pads (no padded copy).
    near_rows = {dy: _reflect_101(ys + dy, h) * w for dy in (-1, 0, 1)}
    near_cols = {dx: _reflect_101(xs + dx, w) for dx in (-1, 0, 1)}

    def at(dy, dx):
        return flat[near_rows[dy] + near_cols[dx]]

    # The 3x3 Sobel derivatives at the candidate pixels only (same numbers as full-image Sobel filters).
    n = {(dy, dx): at(dy, dx) for dy in (-1, 0, 1) for dx in (-1, 0, 1)}
    gx = ((n[-1, 1] - n[-1, -1]) + 2 * (n[0, 1] - n[0, -1]) + (n[1, 1] - n[1, -1])) / 8
    gy = ((n[1, -1] - n[-1, -1]) + 2 * (n[1, 0] - n[-1, 0]) + (n[1, 1] - n[-1, 1])) / 8
    gxx = ((n[-1, 1] - 2 * n[-1, 0] + n[-1, -1]) + 2 * (n[0, 1] - 2 * n[0, 0] + n[0, -1])
           + (n[1, 1] - 2 * n[1, 0] + n[1, -1])) / 4
    gyy = ((n[1, -1] - 2 * n[0, -1] + n[-1, -1]) + 2 * (n[1, 0] - 2 * n[0, 0] + n[-1, 0])
           + (n[1, 1] - 2 * n[0, 1] + n[-1, 1])) / 4
    gxy = (n[1, 1] - n[1, -1] - n[-1, 1] + n[-1, -1]) / 4
    half_diff = 0.5 * (gxx - gyy)
    root = np.sqrt(half_diff * half_diff + gxy * gxy)
    lam = 0.5 * (gxx + gyy) - root  # most negative eigenvalue: curvature across the line
    # Eigenvector of lam (across the line), robust form.
    nx = np.where(half_diff <= 0, gxy, lam - gyy)
    ny = np.where(half_diff <= 0, lam - gxx, gxy)
    norm = np.hypot(nx, ny)
    norm = np.where(norm < 1e-9, 1.0, norm)
    nx, ny = nx / norm, ny / norm
    with np.errstate(divide="ignore", invalid="ignore"):  # lam = 0 (flat): t is inf, t * 0 NaN; both dropped
        t = -(gx * nx + gy * ny) / lam
        ok = (lam < -c.ridge_min_curvature) & (np.abs(t * nx) <= 0.5) & (np.abs(t * ny) <= 0.5)
    # Markings are long: a centre-line point needs enough other centre-line points around it
    # (a line crossing the window gives about its width); specks of grass texture do not.
    # Support counts only neighbours of about the same orientation (a line's points share it,
    # clusters of texture specks do not): 8 orientation bins, a point counts its own and the two
    # adjacent ones.
    k = c.support_window_px
    n_bins = max(1, c.orientation_bins)
    bins = (np.floor((np.arctan2(ny, nx) % np.pi) / (np.pi / n_bins)).astype(int)) % n_bins if n_bins > 1 \
        else np.zeros(len(xs), int)  # one bin: every point's (no orientation needed)
    support = np.zeros(len(xs), np.int32)
    for b in range(n_bins):
        centre = np.zeros_like(candidates)
        sel = ok & (bins == b)
        centre[ys[sel], xs[sel]] = 1
        counts = cv2.boxFilter(centre, cv2.CV_16U, (k, k), normalize=False)
        near = ok & (np.isin(bins, [b, (b + 1) % n_bins, (b - 1) % n_bins]) if n_bins > 2 else np.ones_like(ok))
        support[near] += counts[ys[near], xs[near]]
    kept = np.flatnonzero(ok & (support >= c.min_support))
    t, nx, ny = t[kept], nx[kept], ny[kept]
    points = np.column_stack([xs[kept] + t * nx, ys[kept] + t * ny]).astype(float)
    return points, -lam[kept] / np.maximum(n[0, 0][kept], 1e-6), np.column_stack([nx, ny]), candidates


def marking_channel(bgr: np.ndarray, channel: str) -> np.ndarray:
    """(h, w) uint8 image the markings are looked for in, of an (h, w, 3) BGR image: ``"min"``, the least of each
    pixel's three levels, or ``"luma"``, its grey level.

    White paint raises all three levels, while grass is dark in red and blue: in the least of them the paint stands
    further above the grass than in the luma, and the grass's own light and shade (mowing stripes, wear, a stand's
    shadow), which scale its levels, move it less. Other sports' coloured lines, dark in one level, stand out less.
    """
    if channel == "min":
        blue, green, red = cv2.split(bgr)
        return cv2.min(cv2.min(blue, green), red)
    if channel == "luma":
        return cv2.cvtColor(bgr, cv2.COLOR_BGR2GRAY)
    raise ValueError(f"unknown marking channel '{channel}'; choose 'min' or 'luma'")
