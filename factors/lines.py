"""Line and circle factor: image points on a marking class pulled to its projected 3D element.

For each observed point k of class j the residual is the signed distance (pixels,
distortion included) to the nearest point of the projected polyline of class j:
the 3D element is sampled densely (``MarkingPolylines``), every vertex projected
with the full camera, and the distance taken to the nearest projected segment
(perpendicular distance inside a segment, distance to the end vertex beyond it).
Residuals are divided by sigma_px and go through the per-point Cauchy loss.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from broadtrack_graph.geometry.pitch import LINE_CLASSES, Arc, PitchTemplate
from broadtrack_graph.geometry.state import STATE_SIZE, project_state, rotation_from_angles
from factors.custom import Residuals, custom_factor
from factors.robust import INVALID_RESIDUAL_SIGMAS, robust_rows


@dataclass(frozen=True)
class MarkingPolylines:
    """Dense 3D polylines of the pitch classes.

    vertices_w: class index -> (M_j, 3) metres; class index is the position in ``class_names``.
    class_names: the class names, index -> name.
    """

    vertices_w: tuple[np.ndarray, ...]
    class_names: tuple[str, ...]

    @classmethod
    def from_pitch(cls, pitch: PitchTemplate, step_line_m: float = 1.0, step_arc_m: float = 0.25) -> "MarkingPolylines":
        names = tuple(name for name in LINE_CLASSES if name in pitch.elements)
        vertices = []
        for name in names:
            element = pitch.elements[name]
            step = step_arc_m if isinstance(element, Arc) else step_line_m
            vertices.append(pitch.sample_uniform(step, classes=[name])[name])
        return cls(tuple(vertices), names)

    def class_index(self, name: str) -> int:
        return self.class_names.index(name)


CULL_MARGIN_FRACTION = 0.5
"""Segments with both ends further than this fraction of the image size outside it are
skipped (unless a class has no segment left, then all its segments are used)."""


@dataclass(frozen=True)
class LineSetup:
    """What :func:`line_residuals` needs of a factor's points and classes whatever the camera (made once per factor).

    present: (C,) int, the classes observed, ascending; rows: per present class, the (n_j,) ascending rows of its
    points; u, v: per present class, its points' (n_j, 1) pixel columns.
    vertices_w: (M, 3) metres, the present classes' polyline vertices stacked in that order; seg_start: (S,) int,
    the first vertex of each segment (consecutive vertices of one class); seg_class: (S,) int, its class.
    """

    present: np.ndarray
    rows: tuple[np.ndarray, ...]
    u: tuple[np.ndarray, ...]
    v: tuple[np.ndarray, ...]
    vertices_w: np.ndarray
    seg_start: np.ndarray
    seg_class: np.ndarray

    @classmethod
    def of(cls, uv_px: np.ndarray, class_index: np.ndarray, polylines: MarkingPolylines) -> "LineSetup":
        """The setup of (N, 2) pixels and their (N,) class indices (N >= 1)."""
        present = np.unique(class_index)
        rows = tuple(np.flatnonzero(class_index == j) for j in present)
        blocks = [polylines.vertices_w[j] for j in present]
        vertex_class = np.repeat(present, np.array([len(b) for b in blocks]))
        seg_start = np.flatnonzero(vertex_class[:-1] == vertex_class[1:])
        return cls(present, rows, tuple(uv_px[r, 0][:, None] for r in rows), tuple(uv_px[r, 1][:, None] for r in rows),
                   np.concatenate(blocks), seg_start, vertex_class[seg_start])


def line_residuals(
    state: np.ndarray,
    uv_px: np.ndarray,
    class_index: np.ndarray,
    polylines: MarkingPolylines,
    width_px: int,
    height_px: int,
    want_jacobian: bool = True,
    setup: LineSetup | None = None,
) -> Residuals:
    """Signed pixel distance of each observed point to its class's projected polyline.

    Args:
        state: (8,) camera state ``[f, k1, pan, tilt, roll, Cx, Cy, Cz]``.
        uv_px: (N, 2) observed pixels.
        class_index: (N,) int, index into ``polylines.class_names``.
        polylines: the sampled 3D elements.
        width_px, height_px: image size.
        want_jacobian: False skips the Jacobian.
        setup: ``LineSetup.of(uv_px, class_index, polylines)`` when the caller keeps it (a factor evaluated at
            many states); made here when None.

    Returns:
        residual_px: (N,) signed distance in pixels (0 for invalid points).
        J: (N, 8) d residual / d state (zero rows for invalid points), or None.
        valid: (N,) bool, False where the class has no projected segment in front of the camera.

    Note:
        Vertices beyond the radius where a negative k1 stops being monotonic
        (``1 + 3 k1 r^2 <= 0.05``) are not used: the projection folds back there.
    """
    count = len(uv_px)
    residual = np.zeros(count)
    J = np.zeros((count, STATE_SIZE)) if want_jacobian else None
    valid = np.zeros(count, dtype=bool)
    if count == 0:
        return _line_result(residual, J, valid)
    setup = setup if setup is not None else LineSetup.of(uv_px, class_index, polylines)
    vertices_w = setup.vertices_w
    proj_uv, _, in_front = project_state(state, vertices_w, width_px, height_px, want_jacobian=False)
    R = rotation_from_angles(state[2], state[3], state[4])
    points_c = (vertices_w - state[5:8]) @ R.T
    depth = np.where(in_front, points_c[:, 2], 1.0)
    r2 = (points_c[:, 0] ** 2 + points_c[:, 1] ** 2) / depth**2
    vertex_ok = in_front & (1.0 + 3.0 * state[1] * r2 > 0.05)
    # Segments: consecutive vertices of the same class.
    seg_start, seg_class = setup.seg_start, setup.seg_class
    seg_ok = vertex_ok[seg_start] & vertex_ok[seg_start + 1]
    mx, my = CULL_MARGIN_FRACTION * width_px, CULL_MARGIN_FRACTION * height_px
    u, v = proj_uv[:, 0], proj_uv[:, 1]
    near = (u > -mx) & (u < width_px + mx) & (v > -my) & (v < height_px + my)
    seg_near = seg_ok & (near[seg_start] | near[seg_start + 1])
    # Classes with no segment near the image keep all their valid segments (far-off starts).
    class_near = np.zeros(int(setup.present[-1]) + 1, dtype=bool)
    class_near[seg_class[seg_near]] = True
    keep = seg_near | (seg_ok & ~class_near[seg_class])
    seg_start, seg_class = seg_start[keep], seg_class[keep]
    if len(seg_start) == 0:
        return _line_result(residual, J, valid)
    ax, ay = u[seg_start], v[seg_start]
    ex, ey = u[seg_start + 1] - ax, v[seg_start + 1] - ay
    inv_e2 = 1.0 / np.maximum(ex * ex + ey * ey, 1e-12)
    best = np.zeros(count, dtype=int)
    t_best = np.zeros(count)
    order = np.argsort(seg_class, kind="stable")
    sorted_class = seg_class[order]
    seg_bounds = (np.searchsorted(sorted_class, setup.present, side="left"),
                  np.searchsorted(sorted_class, setup.present, side="right"))
    for rows, pu, pv, lo, hi in zip(setup.rows, setup.u, setup.v, *seg_bounds):
        if hi == lo:
            continue
        segs = order[lo:hi]
        sx, sy = ex[segs], ey[segs]
        dx = pu - ax[segs]
        dy = pv - ay[segs]
        t = np.minimum(np.maximum((dx * sx + dy * sy) * inv_e2[segs], 0.0), 1.0)
        dx -= t * sx
        dy -= t * sy
        dx *= dx
        dy *= dy
        dx += dy
        pick = np.argmin(dx, axis=1)
        best[rows] = segs[pick]
        t_best[rows] = t[np.arange(len(rows)), pick]
        valid[rows] = True
    ox = uv_px[:, 0] - ax[best] - t_best * ex[best]
    oy = uv_px[:, 1] - ay[best] - t_best * ey[best]
    e_b = np.stack([ex[best], ey[best]], axis=1)
    to_q = np.stack([ox, oy], axis=1)  # u - q
    length = np.sqrt(np.einsum("nk,nk->n", e_b, e_b))
    normal = np.stack([-e_b[:, 1], e_b[:, 0]], axis=1) / np.maximum(length, 1e-12)[:, None]
    signed = np.einsum("nk,nk->n", normal, to_q)
    interior = (t_best > 0.0) & (t_best < 1.0)
    end_dist = np.sqrt(np.einsum("nk,nk->n", to_q, to_q))
    sign = np.where(signed >= 0.0, 1.0, -1.0)
    residual = np.where(valid, np.where(interior, signed, sign * end_dist), 0.0)
    if want_jacobian:
        # The Jacobians of the segment ends the points use, each vertex projected once.
        ia = seg_start[best]
        used = np.zeros(len(vertices_w), dtype=bool)
        used[ia] = True
        used[ia + 1] = True
        slot = np.cumsum(used) - 1  # vertex -> its row among the used ones
        _, J_used, _ = project_state(state, vertices_w[used], width_px, height_px)
        Ja, Jb = J_used[slot[ia]], J_used[slot[ia + 1]]
        dq = (1.0 - t_best)[:, None, None] * Ja + t_best[:, None, None] * Jb  # (N, 2, 8)
        direction = np.where(interior[:, None], normal, sign[:, None] * to_q / np.maximum(end_dist, 1e-12)[:, None])
        J = -np.einsum("nk,nks->ns", direction, dq)
        J[~valid] = 0.0
    return _line_result(residual, J, valid)


def _line_result(residual: np.ndarray, J: np.ndarray | None, valid: np.ndarray) -> Residuals:
    return Residuals(residual, None if J is None else [J], valid)


def make_line_factor(
    key: int,
    uv_px: np.ndarray,
    class_index: np.ndarray,
    polylines: MarkingPolylines,
    width_px: int,
    height_px: int,
    sigma_px: float,
    cauchy_scale: float | None,
    loss: str = "cauchy",
):
    """CustomFactor on one camera state: all line points of a frame (residual length N), each point through the
    robust ``loss`` of scale ``cauchy_scale`` sigmas (:func:`factors.robust.robust_rows`)."""
    uv_px = np.ascontiguousarray(uv_px, dtype=float)
    class_index = np.asarray(class_index, dtype=int)
    setup = LineSetup.of(uv_px, class_index, polylines) if len(uv_px) else None

    def fn(vectors, want_jacobian):
        r, Js, valid = line_residuals(vectors[0], uv_px, class_index, polylines, width_px, height_px, want_jacobian,
                                      setup)
        r = np.where(valid, r / sigma_px, INVALID_RESIDUAL_SIGMAS)[:, None]
        Js = None if Js is None else [(Js[0] / sigma_px)[:, None, :]]
        r, Js = robust_rows(r, Js, cauchy_scale, loss)
        return r[:, 0], None if Js is None else [Js[0][:, 0, :]]

    return custom_factor([key], [STATE_SIZE], len(uv_px), fn)
