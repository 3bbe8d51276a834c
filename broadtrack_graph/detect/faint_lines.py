"""Faint straight markings found by their length, not their pixels. No I/O.

Worn or thin paint seen from far away, a low-resolution or heavily compressed frame, a marking smeared across a pan:
a line can stand a few grey levels over the grass, under the level its texture reaches pixel by pixel, so the
ridge detector (:mod:`~broadtrack_graph.detect.ridges`) keeps only its brightest stretches or none of it. Along its
length it stands out all the same: hundreds of pixels a few levels brighter than the grass a few pixels beside them.

Four steps, on the top-hat of the least of each pixel's three levels (white paint raises all three; the coloured
lines of other sports on artificial turf leave one dark):

1. *Weak ridge points.* The ridge detector's centre-line points at a low level (the field's top-hat at its
   ``weak_percentile``, at least ``weak_floor``): the faint paint's and much of the grass texture's, each with the
   direction across its ridge.
2. *Lines they agree on.* Each point votes for the straight lines through it within ``angle_spread_bins`` of its own
   direction (a Hough transform steered by the ridge's direction: a few votes a point, not a full sweep). A line is
   a candidate when its votes stand ``min_z`` standard deviations over what points of that direction scattered over
   the field would give it (their density times its length on the field; Poisson), and ``min_new_votes`` of them
   come from points away from the markings already found (a line they hold whole has nothing to add); at most
   ``max_candidates``, the most voted.
3. *Where the line shows.* Each candidate is first fitted to its ridge (the Hough's directions are a degree apart,
   a few pixels along a long line). Along it, the top-hat on the line (its peak within ``across_px`` across) is
   compared with the band beside it (``band_px`` each side): where its mean over ``window_px`` stands ``margin``
   grey levels over the band for ``min_run_px`` or more, the line's peaks join the markings. Grass texture that
   happened to line up seldom stands over the band beside it for long; a step of light (a mown stripe, a shadow's
   edge) has no top-hat. Points within ``gap_px`` of a marking already found are left to it (a wide line's own
   centre is not found twice), one is kept a pixel, and those more colourful than the ground around them are
   dropped (:func:`~broadtrack_graph.detect.ridges.white`).
4. *Coarser.* A marking blurred by a soft, low-resolution camera (or smeared across by a pan: a 2 px line over 15 px
   at a fifth of its contrast) is a band wider than the ridge detector's reach: its top-hat stands only at the
   band's edges, if at all. The working image is looked at again reduced by each of ``coarse_factors`` (the band
   there a few pixels wide, the noise averaged over the pixels merged), with what the finer scales found taken as
   known, the counts and lengths along a line divided by the factor (:func:`at_factor`) and the same significance
   asked of a line (``min_z``); its points are returned at the working size. Only on a frame read as blurred or
   smeared (:class:`~broadtrack_graph.detect.found_markings.FaintInputs`): on a sharp one the paint is as
   narrow as the ridge detector's reach, and a coarser scale adds only the grass's texture, which a grazing line of
   sight lines up into runs. On a smeared one the cameras the faint traces propose are checked across the smear by
   the smeared image itself (:mod:`~broadtrack_graph.detect.smeared_markings`, asked by
   :mod:`~broadtrack_graph.reinit.confidence`; docs/BENCHMARKS.md, Why the defaults).

The faint look (:func:`with_faint_lines`) adds these points to a frame's markings found already. The tracker takes
it only for the court model's second look at a lost frame whose court camera was not taken, and for the frames of a
chain whose first camera needed it to be confident: on every frame it would cost about as much as the rest of a
1080p frame's tracking (``WeightFreeConfig.faint_lines``; docs/BENCHMARKS.md, Why the defaults).

Pixels are the working image's.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import cv2
import numpy as np

from broadtrack_graph.detect.found_markings import FoundMarkings, marked_points
from broadtrack_graph.detect.image_reads import read_at
from broadtrack_graph.detect.point_cells import pixels_of
from broadtrack_graph.detect.ridges import marking_channel, ridge_points_at, white


@dataclass(frozen=True)
class FaintLineConfig:
    """Settings of :func:`faint_line_points` (module docstring; pixels and grey levels of the working image)."""

    weak_percentile: float = 80.0  # the weak ridge points' level: this percentile of the field's top-hat ...
    weak_floor: float = 4.0  # ... at least this
    angle_bins: int = 180  # the Hough's directions over half a turn
    angle_spread_bins: int = 6  # a point votes for the lines within this many bins of its own direction
    min_votes: int = 30  # a candidate line has at least these votes ...
    min_new_votes: int = 20  # ... these of them from points away from the markings already found ...
    min_z: float = 8.0  # ... standing this many standard deviations over scattered points' (Poisson)
    max_candidates: int = 60  # the most-voted candidates checked
    refine_px: float = 3.0  # a candidate is fitted to the ridge's peaks within this distance across it ...
    across_px: float = 1.0  # ... and then the line's top-hat is its best within this distance across it
    band_px: tuple[int, ...] = (4, 5, 6)  # the band beside it, each side
    margin: float = 3.0  # the line stands this much over the band (grey levels, mean over window_px) ...
    window_px: int = 15
    min_run_px: int = 60  # ... for at least this long
    gap_px: int = 3  # points this close to a marking already found are left to it
    # The image is looked at again reduced by each of these factors (module docstring, step 4); the counts and lengths
    # above (votes, run, window) are working pixels, divided by the factor there, not under coarse_floor.
    coarse_factors: tuple[int, ...] = (2, 3)
    coarse_floor: tuple[int, int, int, int] = (10, 8, 20, 7)  # least min_votes, min_new_votes, min_run_px, window_px


def at_factor(config: FaintLineConfig, factor: int) -> FaintLineConfig:
    """``config`` for the working image reduced ``factor`` times: its counts and lengths along a line divided by
    ``factor`` (a line there holds that many times fewer pixels), not under ``coarse_floor``."""
    if factor == 1:
        return config
    votes, new_votes, run, window = config.coarse_floor
    return replace(config, min_votes=max(votes, config.min_votes // factor),
                   min_new_votes=max(new_votes, config.min_new_votes // factor),
                   min_run_px=max(run, config.min_run_px // factor), window_px=max(window, config.window_px // factor))


def weak_level(tophat: np.ndarray, allowed01: np.ndarray, config: FaintLineConfig) -> float:
    """The weak ridge points' top-hat level: its ``weak_percentile`` over the allowed field, at least ``weak_floor``.

    Args:
        tophat: (h, w) uint8 top-hat; allowed01: (h, w) uint8 0/1, where markings may be.
    """
    sample = tophat[::2, ::2][allowed01[::2, ::2] > 0]
    if len(sample) < 100:
        return config.weak_floor
    return max(config.weak_floor, float(np.percentile(sample, config.weak_percentile)))


def candidate_lines(points: np.ndarray, normals: np.ndarray, allowed01: np.ndarray, config: FaintLineConfig,
                    new: np.ndarray | None = None) -> np.ndarray:
    """Straight lines the weak ridge points agree on (module docstring, step 2).

    Args:
        points: (N, 2) centre-line points, pixels; normals: (N, 2) unit directions across their ridges.
        allowed01: (h, w) uint8 0/1 map where markings may be (the field: a line's expected votes scale with its
            length on it).

    Returns:
        (L, 2) lines as (angle of the normal in [0, pi), signed distance from the origin along it in pixels):
        ``x cos a + y sin a = d``; the most voted first.
    """
    h, w = allowed01.shape
    if len(points) < config.min_votes:
        return np.zeros((0, 2))
    bins = config.angle_bins
    step = np.pi / bins
    own = np.floor((np.arctan2(normals[:, 1], normals[:, 0]) % np.pi) / step).astype(int) % bins
    spread = np.arange(-config.angle_spread_bins, config.angle_spread_bins + 1)
    angle_bin = (own[:, None] + spread[None, :]) % bins
    centres = (np.arange(bins) + 0.5) * step  # each bin's direction, its cosine and sine looked up per vote
    diagonal = int(np.ceil(np.hypot(w, h)))
    distance = np.rint(points[:, 0, None] * np.cos(centres)[angle_bin]
                       + points[:, 1, None] * np.sin(centres)[angle_bin]).astype(int)
    size = 2 * diagonal + 1
    cell = angle_bin * size + distance + diagonal  # (N, S) the accumulator cell of each vote
    votes = np.bincount(cell.ravel(), minlength=bins * size).reshape(bins, size).astype(np.float32)
    enough = votes >= config.min_votes
    if new is not None:  # a line the markings already found hold whole has nothing to add
        new_votes = np.bincount(cell[new].ravel(), minlength=bins * size)
        enough &= new_votes.reshape(bins, size) >= config.min_new_votes
    # A line's votes spread over the directions its points' noisy normals vote for: one peak per spread of them.
    suppressed = cv2.dilate(votes, np.ones((2 * config.angle_spread_bins + 1, 5), np.uint8))
    peaks = np.argwhere((votes >= suppressed) & enough)
    if not len(peaks):
        return np.zeros((0, 2))
    peaks = peaks[np.argsort(-votes[peaks[:, 0], peaks[:, 1]], kind="stable")[:config.max_candidates]]
    lines = np.column_stack([(peaks[:, 0] + 0.5) * step, peaks[:, 1] - diagonal]).astype(float)
    # What points of each direction scattered over the field would give a line of that direction: their density
    # per field pixel (the bins a line's votes come from) times its length on the field.
    per_bin = np.bincount(own, minlength=bins).astype(float)
    from_bins = sum(np.roll(per_bin, -s) for s in spread)  # votes a direction's line can get, from its bins
    density = from_bins / max(1, int(np.count_nonzero(allowed01)))
    samples, inside = _along(lines, (w, h))
    cols = np.clip(samples[..., 0].astype(int), 0, w - 1)
    rows = np.clip(samples[..., 1].astype(int), 0, h - 1)
    length = np.count_nonzero(inside & (allowed01[rows, cols] > 0), axis=1)
    expected = length * density[peaks[:, 0]] + 1.0
    z = (votes[peaks[:, 0], peaks[:, 1]] - expected) / np.sqrt(expected)
    return lines[z >= config.min_z]


def _along(lines: np.ndarray, size: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """((L, T, 2) points 1 px apart along each line over the image's diagonal, (L, T) whether each lies inside the
    image, a pixel clear of its border)."""
    w, h = size
    diagonal = int(np.ceil(np.hypot(w, h)))
    t = np.arange(-diagonal, diagonal, 1.0)
    normal = np.column_stack([np.cos(lines[:, 0]), np.sin(lines[:, 0])])
    direction = np.column_stack([-normal[:, 1], normal[:, 0]])
    samples = lines[:, 1, None, None] * normal[:, None, :] + t[None, :, None] * direction[:, None, :]
    inside = (samples[..., 0] >= 1) & (samples[..., 0] < w - 2) & (samples[..., 1] >= 1) & (samples[..., 1] < h - 2)
    return samples, inside


def shown_stretches(tophat: np.ndarray, allowed01: np.ndarray, lines: np.ndarray, config: FaintLineConfig
                    ) -> np.ndarray:
    """The centre points of each line where it stands over the band beside it (module docstring, step 3).

    Each line is first fitted to its ridge: the Hough's directions are a degree apart, which moves a line a few
    pixels off along a long marking; the ridge's peaks within ``refine_px`` across it, weighted by how far they stand
    over the band, give its direction and place (total least squares).

    Args:
        tophat: (h, w) uint8 top-hat; allowed01: (h, w) uint8 0/1 where markings may be.
        lines: (L, 2) lines of :func:`candidate_lines`.

    Returns:
        (M, 2) pixels: a point a pixel along each shown stretch, at the line's best top-hat across it.
    """
    if not len(lines):
        return np.zeros((0, 2))
    image = tophat.astype(np.float32)
    lines = _fitted(lines, *_profile(image, allowed01, lines, config.refine_px, config.band_px))
    points, stands, on_field = _profile(image, allowed01, lines, config.across_px, config.band_px)
    # Mean over window_px along the line (a running sum, the same at every line).
    L, T = stands.shape
    shown = (_window_mean(stands, config.window_px) >= config.margin) & on_field
    # Runs of shown samples at least min_run_px long.
    edges = np.diff(np.pad(shown.astype(np.int8), ((0, 0), (1, 1))), axis=1)
    line, start = np.nonzero(edges == 1)
    _, end = np.nonzero(edges == -1)
    long_runs = (end - start) >= config.min_run_px
    keep = np.zeros((L, T + 1), np.int32)
    np.add.at(keep, (line[long_runs], start[long_runs]), 1)
    np.add.at(keep, (line[long_runs], end[long_runs]), -1)
    kept = (np.cumsum(keep, axis=1)[:, :T] > 0) & (stands > 0) & np.isfinite(points[..., 0])
    return points[kept]


def _window_mean(values: np.ndarray, k: int) -> np.ndarray:
    """(L, T) the mean of ``values`` (L, T) over ``k`` samples along each row, centred (a running sum; zeros beyond
    the ends)."""
    running = np.cumsum(np.pad(values, ((0, 0), (k // 2 + 1, k - k // 2 - 1))), axis=1)
    return (running[:, k:] - running[:, :-k]) / k


def _profile(image: np.ndarray, allowed01: np.ndarray, lines: np.ndarray, across_px: float,
             band_px: tuple[int, ...]) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Along each line, a pixel apart: ((L, T, 2) the ridge's peak across it within ``across_px``, NaN where the best
    is at the search's edge (no peak), (L, T) how far that peak stands over the band beside it (``band_px`` each
    side; 0 off the field), (L, T) whether the sample lies on the field)."""
    h, w = image.shape
    samples, inside = _along(lines, (w, h))
    used = np.flatnonzero(inside.any(axis=0))  # the stretch of the diagonal the image holds (padded to the longest)
    samples, inside = samples[:, used[0]:used[-1] + 1], inside[:, used[0]:used[-1] + 1]
    L, T = inside.shape
    normal = np.column_stack([np.cos(lines[:, 0]), np.sin(lines[:, 0])])
    on_field = inside & (allowed01[np.clip(np.rint(samples[..., 1]).astype(int), 0, h - 1),
                                   np.clip(np.rint(samples[..., 0]).astype(int), 0, w - 1)] > 0)

    def read(offsets: np.ndarray) -> np.ndarray:  # (L, T, K) the image at these offsets across each line
        at = samples[:, :, None, :] + offsets[None, None, :, None] * normal[:, None, None, :]
        x = at[..., 0].reshape(L, -1).astype(np.float32)
        y = at[..., 1].reshape(L, -1).astype(np.float32)
        return read_at(image, x, y).reshape(L, T, -1)

    across = np.arange(-across_px, across_px + 0.25, 0.5)
    on = read(across)
    best = on.argmax(axis=2)
    band = np.array([s * o for o in band_px for s in (-1, 1)], float)
    stands = np.where(on_field, on.max(axis=2) - read(band).mean(axis=2), 0.0)
    peak = (best > 0) & (best < len(across) - 1)
    points = samples + np.where(peak, across[best], np.nan)[..., None] * normal[:, None, :]
    return points, stands, on_field


def _fitted(lines: np.ndarray, points: np.ndarray, stands: np.ndarray, on_field: np.ndarray) -> np.ndarray:
    """(L, 2) each line fitted to its ridge's peaks (total least squares weighted by how far they stand over the band;
    a line with fewer than three standing peaks is kept as it was). ``points``, ``stands``, ``on_field``: of
    :func:`_profile`."""
    weight = np.where(on_field & np.isfinite(points[..., 0]) & (stands > 0), stands, 0.0)
    points = np.nan_to_num(points)
    total = weight.sum(axis=1)
    ok = np.count_nonzero(weight, axis=1) >= 3
    total = np.where(ok, total, 1.0)
    mean = (weight[..., None] * points).sum(axis=1) / total[:, None]
    d = points - mean[:, None, :]
    sxx, syy = (weight * d[..., 0] ** 2).sum(axis=1), (weight * d[..., 1] ** 2).sum(axis=1)
    sxy = (weight * d[..., 0] * d[..., 1]).sum(axis=1)
    # The normal is the smaller eigenvalue's eigenvector of the weighted scatter: angle of the line's direction
    # 0.5 atan2(2 sxy, sxx - syy), the normal a quarter turn on.
    angle = (0.5 * np.arctan2(2 * sxy, sxx - syy) + np.pi / 2) % np.pi
    distance = mean[:, 0] * np.cos(angle) + mean[:, 1] * np.sin(angle)
    return np.where(ok[:, None], np.column_stack([angle, distance]), lines)


def unknown_map(known: np.ndarray, size: tuple[int, int], gap_px: int) -> np.ndarray:
    """(h, w) uint8 0/1: the pixels of an image of ``size`` (w, h) farther than about ``gap_px`` (a square) from every
    ``known`` point (N, 2) pixels."""
    w, h = size
    near = np.zeros((h, w), np.uint8)
    if len(known) and gap_px > 0:
        k = pixels_of(known, size)
        near[k[:, 1], k[:, 0]] = 1
        near = cv2.dilate(near, np.ones((2 * gap_px + 1, 2 * gap_px + 1), np.uint8))
    return 1 - near


def faint_line_points(colour_bgr: np.ndarray, allowed: np.ndarray, known: np.ndarray, tophat_kernel: np.ndarray,
                      ridge_kernel: np.ndarray, c, config: FaintLineConfig = FaintLineConfig()) -> np.ndarray:
    """The faint straight markings' centre points the ridge detector did not find (module docstring), at the working
    size and at each of ``coarse_factors`` coarser.

    Args:
        colour_bgr: (h, w, 3) uint8 working image.
        allowed: (h, w) uint8, non-zero where markings may be (the field inside its edge, off the players).
        known: (K, 2) the markings' points already found (pixels of the working image).
        tophat_kernel, ridge_kernel, c: the ridge detector's top-hat element, Hessian Gaussian and settings
            (:func:`~broadtrack_graph.detect.ridges.marking_ridges`).

    Returns:
        (M, 2) working pixels.
    """
    size = (colour_bgr.shape[1], colour_bgr.shape[0])
    found = [_points_at_scale(colour_bgr, allowed, known, tophat_kernel, ridge_kernel, c, config)]
    for factor in config.coarse_factors:
        coarse_size = (size[0] // factor, size[1] // factor)
        if min(coarse_size) < 4 * tophat_kernel.shape[0]:
            continue
        # A coarse pixel holds the factor x factor working pixels from factor times its index: its centre is
        # (factor - 1) / 2 on from there.
        rows, cols = coarse_size[1] * factor, coarse_size[0] * factor
        colour = cv2.resize(colour_bgr[:rows, :cols], coarse_size, interpolation=cv2.INTER_AREA)
        # A coarse pixel may hold a marking where all its working pixels may.
        inside = cv2.resize((allowed[:rows, :cols] > 0).astype(np.float32), coarse_size,
                            interpolation=cv2.INTER_AREA) > 1.0 - 1e-6
        centre = (factor - 1) / 2.0
        # What a finer scale found is known here: a line shown there is not traced again, less precisely.
        known_here = np.vstack([known] + found)
        points = _points_at_scale(colour, inside.astype(np.uint8), (known_here - centre) / factor, tophat_kernel,
                                  ridge_kernel, c, at_factor(config, factor))
        found.append(points * factor + centre)
    found = np.vstack(found)
    # One point a pixel: the candidates of one line pivot on it (its points' normals scatter) and trace it again, and
    # so does a line shown at two scales.
    unknown = unknown_map(known, size, config.gap_px)
    pixel = pixels_of(found, size)
    _, first = np.unique(pixel[:, 1] * size[0] + pixel[:, 0], return_index=True)
    first = first[unknown[pixel[first, 1], pixel[first, 0]] > 0]
    found = found[np.sort(first)]
    return found[white(colour_bgr, found, c.faint_max_chroma_rise)]


def _points_at_scale(colour_bgr: np.ndarray, allowed: np.ndarray, known: np.ndarray, tophat_kernel: np.ndarray,
                     ridge_kernel: np.ndarray, c, config: FaintLineConfig) -> np.ndarray:
    """Steps 1-3 of the module docstring on one image: (M, 2) the shown stretches' points, pixels of that image
    (``known``: the points found already, in them too)."""
    tophat = cv2.morphologyEx(marking_channel(colour_bgr, "min"), cv2.MORPH_TOPHAT, tophat_kernel)
    allowed01 = cv2.threshold(allowed, 0, 1, cv2.THRESH_BINARY)[1]
    # The top-hat's border is the image's edge, not grass: a faint run along it is the opening's, not paint's.
    margin = tophat_kernel.shape[0]
    allowed01[:margin], allowed01[-margin:], allowed01[:, :margin], allowed01[:, -margin:] = 0, 0, 0, 0
    size = (tophat.shape[1], tophat.shape[0])
    points, normals = ridge_points_at(tophat, allowed01, weak_level(tophat, allowed01, config), ridge_kernel, c)
    # A line is looked along where the markings found leave it (they need no finding again), its faint stretches
    # told from the others by the whole line's points.
    unknown = unknown_map(known, size, config.gap_px)
    pixel = pixels_of(points, size)
    new = unknown[pixel[:, 1], pixel[:, 0]] > 0
    return shown_stretches(tophat, allowed01, candidate_lines(points, normals, allowed01, config, new), config)


def with_faint_lines(found: FoundMarkings, tophat_kernel: np.ndarray, ridge_kernel: np.ndarray, c,
                     config: FaintLineConfig = FaintLineConfig()) -> FoundMarkings:
    """The faint look: ``found`` with the faint straight paint's points (:func:`faint_line_points`) added to its points
    and marking map, and ``faint_look_of`` the markings it was taken of; ``found`` itself when it offers no faint look
    (``found.faint`` None: not offered, or taken already).

    Args:
        found: a frame's markings (:meth:`~broadtrack_graph.detect.weightfree.WeightFreeDetector.find_markings`).
        tophat_kernel, ridge_kernel, c: the detector's top-hat element, Hessian Gaussian and settings.
    """
    if found.faint is None:
        return found
    if not found.faint.coarse:  # module docstring, step 4
        config = replace(config, coarse_factors=())
    faint = faint_line_points(found.faint.colour_bgr, found.faint.allowed, found.points_work_px, tophat_kernel,
                              ridge_kernel, c, config)
    if not len(faint):
        return replace(found, faint=None, faint_look_of=found)
    points = np.vstack([found.points_work_px, faint])
    detections = replace(found.detections, **marked_points(points, found.work_size, found.scale, c.point_spacing_px))
    # The wide markings' search keeps a finer level's peaked points: the faint points are not.
    wide = found.wide
    if wide is not None:
        wide = replace(wide, peaked=np.concatenate([wide.peaked, np.zeros(len(faint), bool)]))
    return replace(found, detections=detections, points_work_px=points, wide=wide, faint=None, faint_look_of=found)
