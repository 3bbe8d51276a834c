"""The pitch template projected into an image: SoccerNet's sampled polylines and dense curves (numpy only).

Two projections of the same 3D template (:class:`~broadtrack_graph.geometry.pitch.PitchTemplate`):

* :func:`project_template_polylines` builds the image polylines exactly as the official
  SoccerNet camera evaluation does (its sampling, its projection, its border points);
  the metric, the synthetic annotations and the line re-initialisation score with it.
  The rules, kept point for point:

  - every pitch class is sampled as the official template does (lines every 0.9 m,
    circles every 0.2 m of arc; :meth:`PitchTemplate.sample_soccernet`), projected with
    the full distortion model, the distorted normalised coordinates rounded to float32
    as the official code does (so borderline points fall on the same side of a threshold);
  - points behind the camera are skipped, points outside ``[0, W) x [0, H)`` are dropped,
    and where the polyline leaves or enters the image the intersection with the border
    lines x = 0, x = W - 1, y = 0, y = H - 1 nearest the outside (leaving) or inside
    (entering) point is added.

* :class:`TemplateCurves` (dense 3D samples, metres apart) and :func:`project_template`
  (their projection densified to about a pixel in the image) serve the line fit, the
  weight-free detector, the confidence measure and the pictures.

No I/O.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.distortion import distort_normalized
from broadtrack_graph.geometry.paint_width import MARKING_WIDTH_M, painted_widths_px
from broadtrack_graph.geometry.pitch import LINE_CLASSES, Arc, PitchTemplate
from broadtrack_graph.geometry.state import BEHIND_CAMERA_Z

SOCCERNET_LINE_STEP_M = 0.9
"""Sampling step of straight markings in the official SoccerNet evaluation (metres)."""
SOCCERNET_CIRCLE_STEP_M = 0.2
"""Sampling step of circle arcs in the official SoccerNet evaluation (metres of arc)."""


# --------------------------------------------------------------------------- SoccerNet's polylines


class TemplateSampling:
    """The template sampled once as the official evaluation does; reused for every frame.

    Attributes:
        pitch: the template sampled.
        class_names: the sampled classes, in the template's order.
        points_w: (N, 3) metres, pitch frame (z down), every class's samples one after the other.
        offsets: (len(class_names) + 1,) class i owns ``points_w[offsets[i]:offsets[i + 1]]``.
    """

    def __init__(self, pitch: PitchTemplate | None = None) -> None:
        self.pitch = pitch or PitchTemplate()
        samples = self.pitch.sample_soccernet(SOCCERNET_LINE_STEP_M, SOCCERNET_CIRCLE_STEP_M)
        self.class_names: list[str] = list(samples)
        self.points_w = np.vstack([samples[name] for name in self.class_names])
        sizes = [len(samples[name]) for name in self.class_names]
        self.offsets = np.concatenate([[0], np.cumsum(sizes)])

    def __reduce__(self):
        """Pickled as its recipe, the pitch (sampled again on loading: the same points, a few kB sent to a worker
        process instead of tens)."""
        return TemplateSampling, (self.pitch,)


def _project_like_official(camera: Camera, points_w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Project with the full model, rounding distorted normalised coordinates to float32 as the official code does.

    Args:
        camera: the camera (used at its own resolution).
        points_w: (N, 3) metres, pitch frame.

    Returns:
        uv_px: (N, 2) pixels (finite dummies behind the camera); in_front: (N,) bool, depth > 1e-3 m.
    """
    points_c = camera.world_to_camera(points_w)
    in_front = points_c[:, 2] > BEHIND_CAMERA_Z
    depth = np.where(in_front, points_c[:, 2], 1.0)
    xy_n = points_c[:, :2] / depth[:, None]
    xy_d = distort_normalized(xy_n, camera.k1, camera.extra_distortion).astype(np.float32).astype(np.float64)
    uv = camera.focal_px * xy_d + camera.principal_point
    return uv, in_front


def _border_point(inside_or_outside: np.ndarray, previous: np.ndarray, width: int, height: int):
    """Intersection of the line through two image points with the image border lines.

    Args:
        inside_or_outside: (2,) pixels, the current point; previous: (2,) pixels, the point before it.
        width, height: image size in pixels.

    Among the intersections with x = 0, x = W-1, y = 0, y = H-1 that fall inside
    [0, W) x [0, H), the one nearest ``inside_or_outside`` (the current point) is
    returned, first in that side order on ties; None if there is none.
    """
    ex, ey = inside_or_outside
    px, py = previous
    # line = (ex, ey, 1) x (px, py, 1)
    la, lb, lc = ey - py, px - ex, ex * py - ey * px
    best, best_distance = None, math.inf
    for sa, sb, sc in ((1.0, 0.0, 0.0), (1.0, 0.0, -(width - 1.0)), (0.0, 1.0, 0.0), (0.0, 1.0, -(height - 1.0))):
        ix = lb * sc - lc * sb
        iy = lc * sa - la * sc
        iz = la * sb - lb * sa
        if iz == 0.0:
            continue
        ix, iy = ix / iz, iy / iz
        if 0.0 <= ix < width and 0.0 <= iy < height:
            distance = math.hypot(ix - ex, iy - ey)
            if distance < best_distance:
                best, best_distance = (ix, iy), distance
    return best


def project_template_polylines(
    camera: Camera, width_px: int, height_px: int, sampling: TemplateSampling | None = None
) -> dict[str, np.ndarray]:
    """Projected polylines of every class visible in the image, as the official metric builds them.

    Args:
        camera: the camera; rescaled to (width_px, height_px) if it is at another resolution.
        width_px, height_px: evaluation resolution.
        sampling: the template sampling (built once and reused for speed).

    Returns:
        class name -> (K, 2) pixels; classes whose polyline is empty are absent ("not projected").
    """
    sampling = sampling or TemplateSampling()
    camera = camera.rescaled(width_px, height_px)
    uv_all, front_all = _project_like_official(camera, sampling.points_w)
    with np.errstate(invalid="ignore"):
        inside_all = (uv_all[:, 0] >= 0) & (uv_all[:, 0] < width_px) & (uv_all[:, 1] >= 0) & (uv_all[:, 1] < height_px)
    polylines: dict[str, np.ndarray] = {}
    for index, name in enumerate(sampling.class_names):
        start, stop = sampling.offsets[index], sampling.offsets[index + 1]
        front = front_all[start:stop]
        inside = inside_all[start:stop] & front
        if not inside.any():
            continue  # leaving/entering needs at least one point inside
        uv = uv_all[start:stop][front]  # behind-camera points are skipped entirely
        inside = inside[front]
        if inside.all():
            polylines[name] = uv.copy()
            continue
        out: list = []
        # Indices where the inside state changes between consecutive valid points.
        changes = np.flatnonzero(inside[1:] != inside[:-1]) + 1
        position = 0
        state = bool(inside[0])
        for change in list(changes) + [len(uv)]:
            if state:
                if position > 0:  # entering from the previous (outside) point
                    hit = _border_point(uv[position], uv[position - 1], width_px, height_px)
                    if hit is not None:
                        out.append(hit)
                out.extend(map(tuple, uv[position:change]))
                if change < len(uv):  # leaving: border point nearest the first outside point
                    hit = _border_point(uv[change], uv[change - 1], width_px, height_px)
                    if hit is not None:
                        out.append(hit)
            position = change
            state = not state
        polylines[name] = np.asarray(out, dtype=float)
    return polylines


def distances_to_polyline(points_px: np.ndarray, polyline_px: np.ndarray) -> np.ndarray:
    """Euclidean distance of each point to a polyline (minimum over its segments).

    Args:
        points_px: (M, 2) pixels.
        polyline_px: (K, 2) pixels, K >= 1 (a single point is a degenerate polyline).

    Returns:
        (M,) distances in pixels.
    """
    points = np.asarray(points_px, dtype=float)
    poly = np.asarray(polyline_px, dtype=float)
    if len(poly) == 1:
        return np.hypot(*(points - poly[0]).T)
    a = poly[:-1][None, :, :]  # (1, S, 2)
    ab = (poly[1:] - poly[:-1])[None, :, :]
    ap = points[:, None, :] - a  # (M, S, 2)
    length2 = np.sum(ab * ab, axis=2)
    with np.errstate(invalid="ignore", divide="ignore"):
        t = np.sum(ap * ab, axis=2) / length2
    t = np.where(np.isfinite(t), np.clip(t, 0.0, 1.0), 0.0)
    closest = a + t[:, :, None] * ab
    return np.min(np.hypot(*(points[:, None, :] - closest).transpose(2, 0, 1)), axis=1)


# --------------------------------------------------------------------------- dense curves


class TemplateCurves:
    """Dense 3D samples of every pitch class, reused across fits.

    Args:
        pitch: the template (default 105 x 68 m).
        line_step_m, circle_step_m: sampling step of straight markings and of arcs (metres,
            both ends included: :meth:`PitchTemplate.sample_uniform`).

    Attributes:
        pitch: the template; line_step_m, circle_step_m: the steps it was sampled with.
        samples_w: class name -> (L, 3) metres, consecutive samples along the marking.
    """

    def __init__(self, pitch: PitchTemplate | None = None, line_step_m: float = 2.0, circle_step_m: float = 0.5):
        self.pitch = pitch or PitchTemplate()
        self.line_step_m, self.circle_step_m = line_step_m, circle_step_m
        self.samples_w: dict[str, np.ndarray] = {}
        for name, element in self.pitch.elements.items():
            step = circle_step_m if isinstance(element, Arc) else line_step_m
            self.samples_w[name] = self.pitch.sample_uniform(step, classes=[name])[name]
        self._stacked: dict[tuple[str, ...], tuple[np.ndarray, np.ndarray, np.ndarray]] = {}

    def __reduce__(self):
        """Pickled as its recipe, the pitch and the two steps (sampled again on loading: the same samples; a worker
        process starting with tens of kB to read blocks the process that starts it until it has imported)."""
        return TemplateCurves, (self.pitch, self.line_step_m, self.circle_step_m)

    def stacked(self, names) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The samples of several classes one after the other (built once per list of names).

        Returns:
            points_w: (N, 3) metres; class_index: (N,) int16 index into LINE_CLASSES;
            joins_next: (N - 1,) bool, sample i and i + 1 belong to the same class (a segment of it).
        """
        key = tuple(names)
        if key not in self._stacked:
            index = {n: j for j, n in enumerate(LINE_CLASSES)}
            parts = [self.samples_w[n] for n in key]
            points = np.vstack(parts) if parts else np.zeros((0, 3))
            classes = np.concatenate([np.full(len(a), index[n], np.int16) for n, a in zip(key, parts)]) if parts \
                else np.zeros(0, np.int16)
            self._stacked[key] = (points, classes, classes[:-1] == classes[1:])
        return self._stacked[key]


def to_segments(px, py, ax, ay, dx, dy, length2) -> tuple[np.ndarray, np.ndarray]:
    """Points against segments, elementwise (any shapes that broadcast to one, pixels): each point's parameter t in
    [0, 1] of its projection on the segment from (ax, ay) along (dx, dy) (squared length ``length2``, at least a tiny
    positive number), clipped to it, and the squared distance to that point. Arrays made once and updated in place:
    the hot loop of re-initialisation's fits and labelling.

    Returns:
        (t, squared distance), both of the broadcast shape.
    """
    t = (px - ax) * dx
    t += (py - ay) * dy
    t /= length2
    np.clip(t, 0.0, 1.0, out=t)
    dist2 = px - (ax + t * dx)
    dist2 *= dist2
    ey = py - (ay + t * dy)
    ey *= ey
    dist2 += ey
    return t, dist2


def closest_on_polyline(points_px: np.ndarray, poly_px: np.ndarray, valid_seg: np.ndarray):
    """Closest segment of a polyline for each point.

    Args:
        points_px: (M, 2) pixels; poly_px: (L, 2) polyline; valid_seg: (L - 1,) bool, segments that may be used.

    Returns:
        segment index (M,), parameter t in [0, 1] along it (M,), distance in pixels (M,).
    """
    a = poly_px[:-1][valid_seg]
    b = poly_px[1:][valid_seg]
    index = np.flatnonzero(valid_seg)
    d = b - a
    length2 = np.maximum(np.einsum("ij,ij->i", d, d), 1e-12)
    # (M, K): every point against every segment.
    t, dist2 = to_segments(points_px[:, 0:1], points_px[:, 1:2], a[:, 0], a[:, 1], d[:, 0], d[:, 1], length2)
    best = np.argmin(dist2, axis=1)
    rows = np.arange(len(points_px))
    return index[best], t[rows, best], np.sqrt(dist2[rows, best])


@dataclass
class ImageTemplate:
    """Dense projected template samples of one camera.

    uv_px: (N, 2) pixels at the requested size; class_index: (N,) index into LINE_CLASSES;
    width_m_px: (N,) pixels a 12 cm marking's width spans at each sample's depth (f / depth: the image's scale
        there, whatever the line's direction);
    paint_width_px: (N,) image width (pixels) of a 12 cm wide painted line at each sample, across its image: a
        line seen at a grazing angle across the line of sight is foreshortened to a fraction of ``width_m_px``
        (the far lines across a low camera's view, 10-20 times thinner), a line along it is not; None when not
        made.
    """

    uv_px: np.ndarray
    class_index: np.ndarray
    width_m_px: np.ndarray
    paint_width_px: np.ndarray | None = None


KDTREE_FAST_BUILD = {"balanced_tree": False, "compact_nodes": False}
"""scipy cKDTree options for a tree built for one query (a new tree every frame): midpoint splits build about
twice as fast and find the same distances; only where two points lie at exactly the same distance may the
index returned differ (samples of two classes meeting at a corner coincide), so use it where only
distances count."""


def finite_runs(ok: np.ndarray) -> list[tuple[int, int]]:
    """(start, stop) index pairs of the runs of True in a (L,) bool array that hold at least 2 samples."""
    flags = np.concatenate([[False], np.asarray(ok, bool), [False]]).astype(np.int8)
    edges = np.flatnonzero(np.diff(flags))
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2]) if b - a >= 2]


def usable_samples(uv: np.ndarray, front: np.ndarray, width_px: int, height_px: int, margin: float = 2.0) -> np.ndarray:
    """(L,) bool: in front of the camera, finite, and not absurdly far off the image (distortion folds far points back).

    Args:
        uv: (L, 2) projected pixels; front: (L,) bool, in front of the camera.
        width_px, height_px: image size; margin: how far off the image a sample may lie, in image sizes.
    """
    limit = margin * max(width_px, height_px)
    ok = front & np.all(np.isfinite(uv), axis=1)
    with np.errstate(invalid="ignore"):
        ok &= (uv[:, 0] > -limit) & (uv[:, 0] < width_px + limit) & (uv[:, 1] > -limit) & (uv[:, 1] < height_px + limit)
    return ok


def project_template(camera: Camera, curves: TemplateCurves, width_px: int, height_px: int, spacing_px: float = 1.0,
                     classes=None, inside_only: bool = True, paint_widths: bool = False) -> ImageTemplate:
    """Project every class and densify each visible polyline piece to about ``spacing_px``.

    Args:
        camera: any resolution (rescaled to width_px x height_px).
        curves: the 3D samples to project.
        width_px, height_px: image size of the result.
        spacing_px: target distance between consecutive image samples (pixels).
        classes: class names (default: the ground classes, the ones painted on the grass).
        inside_only: keep only samples inside the image.
        paint_widths: also the painted lines' widths across their images (:func:`painted_widths_px`).

    Returns:
        The dense samples, their classes and the image width of a marking at each (and of its paint).
    """
    cam = camera.rescaled(width_px, height_px)
    names = classes if classes is not None else [n for n in LINE_CLASSES if curves.pitch.is_on_ground(n)]
    samples, class_index, joins_next = curves.stacked(names)
    uv, front = cam.project(samples)
    depth = (samples - cam.position_m) @ cam.R_cw[2]
    ok = usable_samples(uv, front, width_px, height_px)
    # Segments between consecutive usable samples of one class whose bounding box meets the image (grown by 2 px).
    lo, hi = np.minimum(uv[:-1], uv[1:]), np.maximum(uv[:-1], uv[1:])
    with np.errstate(invalid="ignore"):
        near = (hi[:, 0] >= -2) & (lo[:, 0] <= width_px + 1) & (hi[:, 1] >= -2) & (lo[:, 1] <= height_px + 1)
    first = np.flatnonzero(ok[:-1] & ok[1:] & joins_next & near)
    if not len(first):
        return ImageTemplate(np.zeros((0, 2)), np.zeros(0, np.int16), np.zeros(0),
                             np.zeros(0) if paint_widths else None)
    paint = None
    if paint_widths:
        paint = painted_widths_px(cam, samples, uv, joins_next)
        paint = np.where(np.isfinite(paint), paint, MARKING_WIDTH_M * cam.focal_px / np.maximum(depth, 1e-3))
    step = np.linalg.norm(uv[first + 1] - uv[first], axis=1)
    count = np.maximum(np.ceil(step / spacing_px).astype(int), 1)
    # Piecewise-linear densification of each kept segment, both ends included.
    seg = np.repeat(first, count + 1)
    t = (np.arange(int(count.sum() + len(count))) - np.repeat(np.cumsum(count + 1) - (count + 1), count + 1)
         ) / np.repeat(count, count + 1)
    uv = uv[seg] + t[:, None] * (uv[seg + 1] - uv[seg])
    dep = depth[seg] + t * (depth[seg + 1] - depth[seg])
    wid = MARKING_WIDTH_M * cam.focal_px / np.maximum(dep, 1e-3)
    cls = class_index[seg]
    if paint is not None:
        paint = paint[seg] + t * (paint[seg + 1] - paint[seg])
    if inside_only:
        keep = (uv[:, 0] >= 0) & (uv[:, 0] <= width_px - 1) & (uv[:, 1] >= 0) & (uv[:, 1] <= height_px - 1)
        uv, cls, wid = uv[keep], cls[keep], wid[keep]
        paint = None if paint is None else paint[keep]
    return ImageTemplate(uv, cls, wid, paint)


def fitting_curves(pitch: PitchTemplate | None = None) -> TemplateCurves:
    """The template sampled as the tracker fits, names and scores it: every 1 m along lines, 0.5 m along circles."""
    return TemplateCurves(pitch or PitchTemplate(), line_step_m=1.0, circle_step_m=0.5)
