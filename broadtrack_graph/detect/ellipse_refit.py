"""A marking ellipse fitted again on the markings' centre points by their distance to it. No I/O.

The ellipses of :mod:`~broadtrack_graph.detect.marking_ellipses` and :mod:`~broadtrack_graph.detect.marking_arcs`
are fitted to the map's pixels: a marking's whole painted width, by an algebraic fit. On a short arc (a penalty arc,
half of it at a frame's edge) the arc fixes its ellipse's position and bend well and the rest of the outline poorly,
and those fits can end a few per cent off in size and a few degrees in angle: enough for the circle-and-line
hypotheses of the court model, which take the ellipse as exact, to miss the camera. A whole ellipse can end as far
off when players stand on the circle, their legs joined to its pieces (the algebraic fit counts their pixels). Here
the ellipse is fitted again on the signed first-order distances of the markings' centre points near it (a point's
error across the marking is then its own, not the paint's width), with a soft-L1 loss, the points gathered again
around the new ellipse. The points of a straight marking across the ellipse are left out (a 16.5 m line where it
meets its arc pulls the fit); a straight marking lying along the ellipse is a piece of the arc that the straight
search took, and stays. The result is another estimate of the same circle's image, not a better one on every frame:
the court model tries both.

Sizes are pixels at 960 px wide (``RefitConfig``), scaled to the frame's width.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.detect.marking_ellipses import ImageEllipse, signed_distances_to_ellipses
from broadtrack_graph.detect.marking_structures import ImageLine


@dataclass(frozen=True)
class RefitConfig:
    """Settings of :func:`refitted_ellipse` (pixels at 960 px wide)."""

    near_px: float = 3.0  # a centre point within this of the ellipse is on it ...
    line_clearance_px: float = 2.0  # ... unless within this of a straight marking across it (inside its extent)
    min_points: int = 12  # fewer points: no refit
    rounds: int = 2  # fits, the points gathered again around each
    iterations: int = 20  # Levenberg-Marquardt steps of a round
    robust_scale_px: float = 0.7  # the soft-L1 loss's scale: points further off count as their distance
    min_change_px: float = 0.5  # a refit moving no point of the outline by this much is not a new estimate


def refitted_ellipse(ellipse: ImageEllipse, points_px: np.ndarray, frame_width_px: int,
                     lines: list[ImageLine] = (), config: RefitConfig = RefitConfig()) -> ImageEllipse | None:
    """The ellipse fitted again on the centre points near it (module docstring), or None when too few points are
    near it, the fit leaves the points or does not move the outline by ``min_change_px``.

    Args:
        ellipse: a marking ellipse, frame pixels.
        points_px: (N, 2) the markings' centre points, frame pixels.
        frame_width_px: the frame's width (the settings are at 960 px).
        lines: the map's straight markings, frame pixels: their points are left out.
    """
    unit = frame_width_px / 960.0
    points = np.asarray(points_px, float).reshape(-1, 2)
    crossing = [line for line in lines if not _along(line, ellipse, config.near_px * unit)]
    points = points[~_near_lines(points, crossing, config.line_clearance_px * unit)]
    current = ellipse
    for _ in range(config.rounds):
        near = points[current.distances_px(points) < config.near_px * unit]
        if len(near) < config.min_points:
            return None
        current = _fitted(current, near, config.iterations, config.robust_scale_px * unit)
        if current is None:
            return None
    near = points[current.distances_px(points) < config.near_px * unit]
    if len(near) < config.min_points or same_ellipse(ellipse, current, frame_width_px, config):
        return None
    return ImageEllipse(current.centre_px, current.semi_axes_px, current.angle_rad, ellipse.support_px)


def _fitted(start: ImageEllipse, points: np.ndarray, iterations: int, scale_px: float) -> ImageEllipse | None:
    """The ellipse through the points minimising the soft-L1 sum of their first-order distances (scale_px: points
    further off count as their distance, not its square), from start: Levenberg-Marquardt on (centre, log semi-axes,
    angle), the Jacobian by central differences (the ten shifted ellipses' distances in one pass), the robust weights
    made again at each step, at most ``iterations`` steps (a short arc leaves the ellipse's far side loose: the steps
    stop before it wanders). Written here rather than through scipy's ``least_squares``, whose bounded trust-region
    method took about twice the time on these five-parameter fits."""
    span = float(np.ptp(points, axis=0).max()) + 1.0
    log_max = math.log(100.0 * span)  # the semi-axes between a pixel and a hundred spans of the points
    params = np.array([*start.centre_px, math.log(start.semi_axes_px[0]), math.log(start.semi_axes_px[1]),
                       start.angle_rad])
    if not np.all((params[2:4] > 0.0) & (params[2:4] < log_max)):
        return None

    def distances(*vectors: np.ndarray) -> np.ndarray:  # (K, N): one row for each parameter vector
        return signed_distances_to_ellipses([(v[:2], np.exp(np.clip(v[2:4], 0.0, log_max)), v[4]) for v in vectors],
                                            points)

    def cost(r: np.ndarray) -> float:
        return float(np.sum(np.sqrt(1.0 + (r / scale_px) ** 2) - 1.0))

    steps = np.array([1e-3 * span, 1e-3 * span, 1e-4, 1e-4, 1e-4])
    damping = 1e-3
    with np.errstate(all="ignore"):
        r = distances(params)[0]
        current = cost(r)
        for _ in range(iterations):
            shifted = distances(*(params + np.diag(steps)), *(params - np.diag(steps)))  # (10, N): + then -
            J = np.ascontiguousarray(((shifted[:5] - shifted[5:]) / (2.0 * steps)[:, None]).T)  # (N, 5)
            weight = 1.0 / np.sqrt(1.0 + (r / scale_px) ** 2)
            A, g = (J * weight[:, None]).T @ J, (J * weight[:, None]).T @ r
            improved = False
            for _ in range(6):
                try:
                    candidate = params - np.linalg.solve(A + damping * np.diag(np.diag(A) + 1e-12), g)
                except np.linalg.LinAlgError:
                    damping *= 10.0
                    continue
                r_candidate = distances(candidate)[0]
                value = cost(r_candidate)
                if np.isfinite(value) and value < current:
                    params, r, improved = candidate, r_candidate, current - value > 1e-6 * current
                    current, damping = value, max(damping / 10.0, 1e-9)
                    break
                damping *= 10.0
            if not improved:
                break
    if not np.isfinite(params).all():
        return None
    a, b = np.exp(np.clip(params[2:4], 0.0, log_max))
    angle = float(params[4])
    if b > a:
        a, b, angle = b, a, angle + math.pi / 2
    return ImageEllipse(params[:2].copy(), (float(a), float(b)), angle % math.pi, start.support_px)


def _along(line: ImageLine, ellipse: ImageEllipse, near_px: float, samples: int = 9) -> bool:
    """Whether the straight marking lies along the ellipse (a piece of a bent arc the straight search took as a
    line): its stretch's points within near_px of the ellipse at the median."""
    lo, hi = line.extent_px
    stretch = line.centre_px + np.linspace(lo, hi, samples)[:, None] * np.asarray(line.direction, float)
    return bool(np.median(ellipse.distances_px(stretch)) < near_px)


def _near_lines(points: np.ndarray, lines: list[ImageLine], clearance_px: float) -> np.ndarray:
    """(N,) bool: the points within clearance_px of a straight marking, inside its extent (its support's 10th to 90th
    percentile along it, widened by a fifth of its length and clearance_px)."""
    near = np.zeros(len(points), bool)
    for line in lines:
        offset = points - line.centre_px
        along = offset @ np.asarray(line.direction, float)
        across = np.abs(offset @ np.asarray(line.normal, float))
        lo, hi = line.extent_px
        lo, hi = lo - 0.2 * (hi - lo), hi + 0.2 * (hi - lo)
        near |= (across < clearance_px) & (along > lo - clearance_px) & (along < hi + clearance_px)
    return near


def same_ellipse(a: ImageEllipse, b: ImageEllipse, frame_width_px: int, config: RefitConfig = RefitConfig(),
                 samples: int = 64) -> bool:
    """Whether b lies within ``min_change_px`` of a's whole outline (a's outline sampled, first-order distances)."""
    return float(b.distances_px(a.outline_px(samples)).max()) < config.min_change_px * frame_width_px / 960.0
