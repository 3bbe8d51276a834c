"""The weight-free detector's marking ridges: thin bright lines on grass, to sub-pixel centre-line points. No I/O.

A white top-hat of the grey working image keeps structures up to about the kernel's width brighter than their
surroundings; its pixels above a threshold (a fixed level, or above the level the grass texture reaches on the
frame) where markings may be are the candidates. Each candidate is moved to the sub-pixel centre of its ridge with
Steger's method: the Hessian of the smoothed top-hat gives the direction across the line (its most negative
eigenvalue's eigenvector) and the offset along it; a candidate whose centre lies within half a pixel, on a ridge
curved enough, and with enough other centre-line points around it (a marking is long, a speck of texture is not)
is kept. Derivatives are taken at the candidate pixels only.
"""

from __future__ import annotations

import cv2
import numpy as np


def _reflect_101(index: np.ndarray, size: int) -> np.ndarray:
    """Indices in [-1, size] mapped into [0, size) as OpenCV's BORDER_REFLECT_101 pads (-1 -> 1, size -> size - 2)."""
    return (size - 1) - np.abs((size - 1) - np.abs(index)) if size > 1 else np.zeros_like(index)


def marking_ridges(grey: np.ndarray, allowed: np.ndarray, grass: np.ndarray | None, tophat_kernel: np.ndarray,
                   ridge_kernel: np.ndarray, c) -> tuple[np.ndarray, np.ndarray]:
    """Sub-pixel centre-line points (N, 2) (working pixels) and the candidate map (uint8) (module docstring).

    Args:
        grey: (h, w) uint8 grey working image (already pre-smoothed as needed).
        allowed: (h, w) uint8, non-zero where markings may be.
        grass: (h, w) uint8 grass mask, or None; the threshold adapts to the top-hat of grass texture and noise there.
        tophat_kernel: the top-hat's structuring element (``tophat_kernel_px`` square).
        ridge_kernel: the 1-D float32 Gaussian of the Hessian's scale (``ridge_sigma_px``), applied along both axes.
        c: the detector's settings (:class:`~broadtrack_graph.detect.weightfree.WeightFreeConfig`: its threshold,
            support and curvature fields).
    """
    tophat = cv2.morphologyEx(grey, cv2.MORPH_TOPHAT, tophat_kernel)
    threshold = c.tophat_threshold
    if grass is not None:
        sample = tophat[::4, ::4][grass[::4, ::4] > 0]  # markings are a few per cent of the grass
        if len(sample) > 100:
            threshold = max(threshold, float(np.percentile(sample, 90)) + c.tophat_noise_margin)
    candidates = cv2.bitwise_and(cv2.threshold(tophat, threshold, 1, cv2.THRESH_BINARY)[1],
                                 cv2.threshold(allowed, 0, 1, cv2.THRESH_BINARY)[1])
    found = cv2.findNonZero(candidates)
    if found is None:
        return np.zeros((0, 2)), candidates
    found = found.reshape(-1, 2)
    xs, ys = found[:, 0], found[:, 1]
    h, w = grey.shape
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
    ok &= support >= c.min_support
    points = np.column_stack([xs[ok] + t[ok] * nx[ok], ys[ok] + t[ok] * ny[ok]]).astype(float)
    return points, candidates

