"""SoccerNet lens distortion in normalised image coordinates: the model's terms, distortion and its inverse.

The model: rational radial (k1..k3 over k4..k6), tangential (p1, p2) and thin prism (s1..s4),
applied to ``x_n = Xc_xy / Xc_z``; the tracker estimates k1 only. Numbers only, no I/O.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class ExtraDistortion:
    """Distortion terms beyond k1 (SoccerNet camera format), normalised coordinates.

    radial_k2_k6: k2, k3 (numerator r^4, r^6) and k4, k5, k6 (denominator r^2, r^4, r^6).
    tangential_p1_p2: tangential terms.
    thin_prism_s1_s4: thin-prism terms.
    """

    radial_k2_k6: tuple[float, float, float, float, float] = (0.0,) * 5
    tangential_p1_p2: tuple[float, float] = (0.0, 0.0)
    thin_prism_s1_s4: tuple[float, float, float, float] = (0.0,) * 4

    @property
    def is_zero(self) -> bool:
        return not any(self.radial_k2_k6) and not any(self.tangential_p1_p2) and not any(self.thin_prism_s1_s4)


NO_EXTRA_DISTORTION = ExtraDistortion()


def unfolded_radius2(k1: float, extra: ExtraDistortion = NO_EXTRA_DISTORTION) -> float:
    """Squared normalised radius up to which the radial distortion still grows with the radius.

    With k1 < 0 the distorted radius ``r (1 + k1 r^2)`` peaks at ``r^2 = 1 / (3 |k1|)`` and falls
    beyond it: points far outside the image fold back into it. A projection is only meaningful
    inside this radius (inf when the distortion never folds; tangential and thin-prism terms are
    left out, they are small).
    """
    k2, k3, k4, k5, k6 = extra.radial_k2_k6
    if not any((k2, k3, k4, k5, k6)):
        return math.inf if k1 >= 0.0 else 1.0 / (3.0 * -k1)
    r = np.linspace(0.0, 20.0, 4001)
    r2 = r * r
    radial = r * (1.0 + k1 * r2 + k2 * r2**2 + k3 * r2**3) / (1.0 + k4 * r2 + k5 * r2**2 + k6 * r2**3)
    falling = np.flatnonzero(np.diff(radial) <= 0.0)
    return float(r2[falling[0]]) if len(falling) else math.inf


def distort_normalized(xy_n: np.ndarray, k1: float, extra: ExtraDistortion = NO_EXTRA_DISTORTION) -> np.ndarray:
    """Apply lens distortion to normalised image coordinates.

    Args:
        xy_n: (N, 2) undistorted normalised coordinates (Xc_x / Xc_z, Xc_y / Xc_z).
        k1: first radial coefficient.
        extra: the other SoccerNet distortion terms.

    Returns:
        (N, 2) distorted normalised coordinates.
    """
    x = xy_n[:, 0]
    y = xy_n[:, 1]
    r2 = x * x + y * y
    if extra.is_zero:
        factor = 1.0 + k1 * r2
        return xy_n * factor[:, None]
    k2, k3, k4, k5, k6 = extra.radial_k2_k6
    p1, p2 = extra.tangential_p1_p2
    s1, s2, s3, s4 = extra.thin_prism_s1_s4
    r4 = r2 * r2
    r6 = r4 * r2
    factor = (1.0 + k1 * r2 + k2 * r4 + k3 * r6) / (1.0 + k4 * r2 + k5 * r4 + k6 * r6)
    xd = x * factor + 2.0 * p1 * x * y + p2 * (r2 + 2.0 * x * x) + s1 * r2 + s2 * r4
    yd = y * factor + 2.0 * p2 * x * y + p1 * (r2 + 2.0 * y * y) + s3 * r2 + s4 * r4
    return np.stack([xd, yd], axis=1)


def undistort_normalized(
    xy_d: np.ndarray,
    k1: float,
    extra: ExtraDistortion = NO_EXTRA_DISTORTION,
    iterations: int = 30,
) -> np.ndarray:
    """Invert :func:`distort_normalized` iteratively.

    With k1 only, Newton's method on the radius ``r (1 + k1 r^2) = r_d`` (quadratic
    convergence). With the full model, Newton's method in 2-D with a
    finite-difference Jacobian.

    Args:
        xy_d: (N, 2) distorted normalised coordinates.
        k1: first radial coefficient.
        extra: the other distortion terms.
        iterations: maximum Newton steps.

    Returns:
        (N, 2) undistorted normalised coordinates.

    Note:
        With k1 < 0 the map is invertible only for ``r_d < 2 / (3 sqrt(3 |k1|))``;
        beyond that the radius of the turning point is returned.
    """
    xy_d = np.asarray(xy_d, dtype=float)
    if extra.is_zero:
        if k1 == 0.0:
            return xy_d.copy()
        r_d = np.hypot(xy_d[:, 0], xy_d[:, 1])
        r = r_d.copy()
        r_max = 1.0 / math.sqrt(3.0 * -k1) if k1 < 0 else np.inf
        for _ in range(iterations):
            r2 = r * r  # products, not r**3: numpy's power calls pow() for a float exponent, 25x slower
            g = r + k1 * (r2 * r) - r_d
            dg = 1.0 + 3.0 * k1 * r2
            step = g / np.where(np.abs(dg) < 1e-12, 1e-12, dg)
            r = np.clip(r - step, 0.0, r_max)
            if np.max(np.abs(step), initial=0.0) < 1e-15:
                break
        scale = np.where(r_d > 0, r / np.where(r_d > 0, r_d, 1.0), 1.0)
        return xy_d * scale[:, None]
    xy = xy_d.copy()
    eps = 1e-7
    for _ in range(iterations):
        residual = distort_normalized(xy, k1, extra) - xy_d
        jx = (distort_normalized(xy + [eps, 0.0], k1, extra) - distort_normalized(xy - [eps, 0.0], k1, extra)) / (2 * eps)
        jy = (distort_normalized(xy + [0.0, eps], k1, extra) - distort_normalized(xy - [0.0, eps], k1, extra)) / (2 * eps)
        det = jx[:, 0] * jy[:, 1] - jy[:, 0] * jx[:, 1]
        det = np.where(np.abs(det) < 1e-12, 1e-12, det)
        dx = (jy[:, 1] * residual[:, 0] - jy[:, 0] * residual[:, 1]) / det
        dy = (-jx[:, 1] * residual[:, 0] + jx[:, 0] * residual[:, 1]) / det
        xy[:, 0] -= dx
        xy[:, 1] -= dy
        if np.max(np.abs(residual), initial=0.0) < 1e-15:
            break
    return xy
