"""Ground homographies refitted on every straight marking they explain (court-model calibration). No I/O.

A hypothesis of :mod:`broadtrack_graph.reinit.court_lines` rests on four image lines, and in a narrow view two
nearly parallel lines place a vanishing point poorly: the homography can be tens of pixels off while other
markings in view would pin it. :func:`refit_on_lines` puts each image line on the pitch line the hypothesis draws
nearest to it (both ends within a gate) and solves the homography again from all of those correspondences at once
(the direct linear transform of lines: a pitch line ``l`` and an image point ``x`` on its image give
``l . (G x) = 0`` for ``G = H^-1``), every hypothesis at once, twice (the second time with the first fit's pairing).

Image coordinates are normalised as in :mod:`broadtrack_graph.reinit.court_lines`; pitch frame in metres.
"""

from __future__ import annotations

import numpy as np

from broadtrack_graph.geometry.matrices import inverses

PITCH_SCALE_M = 50.0
"""Pitch coordinates are divided by this in the linear solve (its conditioning)."""


def pitch_lines(along_x: np.ndarray, along_y: np.ndarray) -> np.ndarray:
    """(M, 3) homogeneous pitch lines ``(a, b, c) . (x, y, 1) = 0`` of the ``y = c`` and ``x = c`` markings."""
    rows = [(0.0, 1.0, -c) for c in along_x] + [(1.0, 0.0, -c) for c in along_y]
    return np.array(rows, float).reshape(-1, 3)


def refit_on_lines(H_n: np.ndarray, ends_n: np.ndarray, lines_w: np.ndarray, gate_n: float, min_lines: int = 5,
                   rounds: int = 2) -> tuple[np.ndarray, np.ndarray]:
    """The homographies solved again from every image line each one puts near a pitch line.

    Args:
        H_n: (K, 3, 3) hypotheses, pitch (x, y, 1) metres -> normalised image points.
        ends_n: (L, 2, 2) the two ends of each image line, normalised coordinates.
        lines_w: (M, 3) pitch lines (:func:`pitch_lines`).
        gate_n: an image line is put on a pitch line when both its ends lie within this of the line's image.
        min_lines: hypotheses explaining fewer image lines (with both directions among them) are not refitted.

    Returns:
        (K, 3, 3) the homographies (refitted, or as given) and (K,) bool: which were refitted.
    """
    H_n = np.asarray(H_n, float).reshape(-1, 3, 3)
    K, L = len(H_n), len(ends_n)
    refitted = np.zeros(K, bool)
    if K == 0 or L < min_lines or len(lines_w) == 0:
        return H_n, refitted
    x = np.concatenate([ends_n, np.ones((L, 2, 1))], axis=2)  # (L, 2, 3)
    scale = np.diag([PITCH_SCALE_M, PITCH_SCALE_M, 1.0])  # scaled pitch (x / 50, y / 50, 1) -> metres
    lines_s = lines_w @ scale  # the pitch lines in scaled coordinates (a line l acts on scale @ p_s)
    family = (np.abs(lines_w[:, 0]) > 0.5).astype(int)  # 0: y = c, 1: x = c
    current = H_n.copy()
    for _ in range(rounds):
        with np.errstate(divide="ignore", invalid="ignore"):
            images = np.einsum("kji,mj->kmi", inverses(current), lines_w)  # l_img = H^-T l  (K, M, 3)
            images = images / np.linalg.norm(images[..., :2], axis=2, keepdims=True)
            distance = np.abs(np.einsum("kmi,lei->klme", images, x))  # (K, L, M, 2)
        worst = np.nan_to_num(distance.max(axis=3), nan=np.inf)  # (K, L, M)
        nearest = worst.argmin(axis=2)  # (K, L)
        paired = np.take_along_axis(worst, nearest[..., None], axis=2)[..., 0] < gate_n  # (K, L)
        fam = family[nearest]
        ok = (paired.sum(axis=1) >= min_lines) & ((paired & (fam == 0)).any(axis=1)) & \
            ((paired & (fam == 1)).any(axis=1))
        if not ok.any():
            break
        # Rows kron(l_s, x) of l_s . (G_s x) = 0, zero where a line is not paired: (K, 2L, 9).
        rows = np.einsum("kla,leb->kleab", lines_s[nearest], x).reshape(K, 2 * L, 9)
        rows = rows * np.repeat(paired, 2, axis=1)[..., None]
        _, _, vt = np.linalg.svd(rows[ok])
        G_s = vt[:, -1].reshape(-1, 3, 3)  # image -> scaled pitch
        with np.errstate(divide="ignore", invalid="ignore"):
            H_new = inverses(G_s) @ np.linalg.inv(scale)[None]  # metres -> image: H = G_s^-1 S^-1
        good = np.all(np.isfinite(H_new), axis=(1, 2))
        index = np.flatnonzero(ok)[good]
        current[index] = H_new[good]
        refitted[index] = True
    return current, refitted
