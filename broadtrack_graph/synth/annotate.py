"""Ground truth of a rendered frame: SoccerNet line annotations, class masks, keypoints.

Annotations are made the way a human annotator makes them, but from the exact
geometry:

* a class is annotated when the official metric projects it into the image
  (:func:`broadtrack_graph.geometry.template.project_template_polylines`: at least one of its
  0.9 m / 0.2 m samples in front of the camera and inside the image); a marking that
  only grazes a corner between two samples is left out, as the metric ignores it;
* its points are taken on the visible parts only: inside the image, and where the
  rendered pixel really shows that marking (the ground for painted lines, the goal
  frame for posts and crossbars), so players and goal posts cut the lines; a handful
  of points per visible piece, more on circles, like the real SoccerNet files;
* with k1 < 0 (given camera tracks only), points far off the optical axis are folded
  back into the image by the model; no pixel shows them, so they are never annotated,
  and a class the metric projects only that way is listed in ``folded_classes``;
* points farther than 2 px from the metric's own polyline of the class are dropped:
  this only happens next to the image border, where the metric approximates the
  marking by a chord to a far-away sample (see ``_reachable``);
* a class that is projected into the image but hidden everywhere (a short piece
  behind a player) is still annotated from the geometry, and listed in
  ``occluded_classes`` so users can tell; without it the metric would count the
  ground-truth camera's projection as a false positive.

Coordinates are normalised with SoccerNet's rule: x / (W - 1), y / (H - 1).
No I/O here.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import LINE_CLASSES, Arc, PitchTemplate
from broadtrack_graph.geometry.template import TemplateSampling, distances_to_polyline, project_template_polylines
from broadtrack_graph.synth.drawing import SURFACE_GOAL, SURFACE_GROUND, SURFACE_PLAYER, fixed_point
from broadtrack_graph.synth.scene import DEFAULT_STADIUM

DENSE_SAMPLES = 3000  # samples per element when looking for its visible parts
LINE_POINT_SPACING_PX = 600.0  # about one annotated point per this many pixels on straight lines (real files: ~2 per line)
CIRCLE_POINT_SPACING_PX = 70.0  # on circles (real files: ~10 per arc)
MIN_PIECE_PX = 3.0  # visible pieces shorter than this are skipped (unless nothing else is visible)
METRIC_REACH_PX = 2.0  # annotated points stay this close to the metric's polyline (see _reachable)


@dataclass
class FrameTruth:
    """Ground truth of one frame.

    lines_norm: class -> (N, 2) SoccerNet annotation points, normalised coordinates.
    occluded_classes: classes projected into the image but fully hidden (annotated from geometry).
    keypoints_px: template keypoint name -> (2,) pixel position, for visible keypoints.
    mask: (H, W) uint8, LINE_CLASSES index + 1 of the visible marking at each pixel, 0 = none.
    folded_classes: classes the metric projects into the image only through the fold of a
        k1 < 0 distortion (points far off-axis mapped back into the image); not annotated, as
        no pixel shows them there. Never happens with k1 >= 0 (all generated tracks).
    """

    lines_norm: dict[str, np.ndarray]
    occluded_classes: list[str] = field(default_factory=list)
    keypoints_px: dict[str, np.ndarray] = field(default_factory=dict)
    mask: np.ndarray | None = None
    folded_classes: list[str] = field(default_factory=list)


class Annotator:
    """Builds FrameTruth for rendered frames (reuses the template samplings)."""

    def __init__(self, pitch: PitchTemplate | None = None) -> None:
        self.pitch = pitch or PitchTemplate()
        self.sampling = TemplateSampling(self.pitch)
        fractions = np.linspace(0.0, 1.0, DENSE_SAMPLES)
        self.dense_w = {name: self.pitch.elements[name].points_at(fractions) for name in LINE_CLASSES}
        self.keypoint_names = list(self.pitch.keypoints)
        self.keypoints_w = self.pitch.keypoint_array(self.keypoint_names)

    def annotate(self, camera: Camera, labels: np.ndarray, class_ids: np.ndarray | None = None,
                 want_mask: bool = True) -> FrameTruth:
        """Ground truth of one frame.

        Args:
            camera: the frame's camera at the image resolution.
            labels: (H, W) surface labels of the rendered frame (drawing.SURFACE_*).
            class_ids: (H, W) marking class id + 1 under each ground pixel (RenderedFrame.class_ids),
                needed for the mask.
            want_mask: build the per-class mask.
        """
        height_px, width_px = labels.shape
        camera = camera.rescaled(width_px, height_px)
        projected = project_template_polylines(camera, width_px, height_px, self.sampling)
        # An annotator clicks on a marking, not on the edge of a player in front of it: a
        # point counts as visible when its pixel and the 8 around it show the marking's surface
        # (the goal tubes may be thinner than 3 px: their pixel must be a tube, no player around).
        kernel = np.ones((3, 3), np.uint8)
        clear_ground = cv2.erode((labels == SURFACE_GROUND).astype(np.uint8), kernel) > 0
        clear_goal = (labels == SURFACE_GOAL) & (cv2.erode((labels != SURFACE_PLAYER).astype(np.uint8), kernel) > 0)
        scale = np.array([width_px - 1.0, height_px - 1.0])
        lines: dict[str, np.ndarray] = {}
        occluded: list[str] = []
        folded: list[str] = []
        ground_lines_px: dict[str, np.ndarray] = {}
        for name in LINE_CLASSES:
            uv, front = camera.project(self.dense_w[name])
            front &= _unfolded(camera, self.dense_w[name])
            with np.errstate(invalid="ignore"):
                inside = front & (uv[:, 0] >= 0) & (uv[:, 0] <= width_px - 1) & (uv[:, 1] >= 0) & (uv[:, 1] <= height_px - 1)
            expected = SURFACE_GROUND if self.pitch.is_on_ground(name) else SURFACE_GOAL
            visible = inside.copy()
            if inside.any():
                cols = np.rint(uv[inside, 0]).astype(int)
                rows = np.rint(uv[inside, 1]).astype(int)
                clear = clear_ground if expected == SURFACE_GROUND else clear_goal
                visible[inside] = clear[rows, cols]
            if expected == SURFACE_GROUND and want_mask:
                ground_lines_px[name] = np.where((front & np.isfinite(uv).all(axis=1))[:, None], uv, np.nan)
            if name not in projected:
                continue
            is_circle = isinstance(self.pitch.elements[name], Arc)
            points = _reachable(_pick_points(uv, visible, is_circle), projected[name])
            if not len(points) and camera.k1 >= 0:  # the metric's own sample points that are visible (never folded)
                points = _visible_vertices(projected[name], clear_ground if expected == SURFACE_GROUND else clear_goal)
            if not len(points):
                points = _reachable(_pick_points(uv, inside, is_circle), projected[name])
                if len(points):
                    occluded.append(name)
            if not len(points):
                if camera.k1 < 0:
                    folded.append(name)  # only folded-in by the k1 < 0 model: nothing to see, not annotated
                    continue
                # In the image only between x = W - 1 and W (or y): use the metric's own points.
                polyline = projected[name]
                points = np.clip(polyline[:: max(1, len(polyline) // 4)], 0, scale)
            lines[name] = points / scale
        keypoints = self._keypoints(camera, labels)
        mask = self._mask(camera, labels, class_ids, ground_lines_px) if want_mask else None
        return FrameTruth(lines_norm=lines, occluded_classes=occluded, keypoints_px=keypoints, mask=mask,
                          folded_classes=folded)

    def _keypoints(self, camera: Camera, labels: np.ndarray) -> dict[str, np.ndarray]:
        height_px, width_px = labels.shape
        uv, front = camera.project(self.keypoints_w)
        front &= _unfolded(camera, self.keypoints_w)
        out = {}
        for k, name in enumerate(self.keypoint_names):
            if not front[k]:
                continue
            u, v = uv[k]
            if not (0 <= u <= width_px - 1 and 0 <= v <= height_px - 1):
                continue
            label = labels[int(round(v)), int(round(u))]
            ok = label == SURFACE_GROUND or (name.startswith("Goal") and label == SURFACE_GOAL)
            if ok:
                out[name] = uv[k].copy()
        return out

    def _mask(self, camera: Camera, labels: np.ndarray, class_ids, ground_lines_px) -> np.ndarray:
        """Per-class mask: markings under ground pixels (at least 1 px wide), goal tubes where drawn."""
        height_px, width_px = labels.shape
        thin = np.zeros((height_px, width_px), np.uint8)
        for name, uv in ground_lines_px.items():
            for piece in _finite_pieces(uv, width_px, height_px):
                cv2.polylines(thin, [fixed_point(piece)], False, LINE_CLASSES.index(name) + 1, 1,
                              cv2.LINE_8, 4)
        mask = np.zeros((height_px, width_px), np.uint8) if class_ids is None else class_ids.copy()
        ground = labels == SURFACE_GROUND
        fill = ground & (mask == 0)
        mask[fill] = thin[fill]
        mask[~ground] = 0
        goal = np.zeros_like(mask)
        for name in LINE_CLASSES:
            if self.pitch.is_on_ground(name):
                continue
            points_w = self.dense_w[name][:: DENSE_SAMPLES // 60]
            uv, front = camera.project(points_w)
            if not front.all():
                continue
            depth = float(np.linalg.norm(np.mean(points_w, axis=0) - camera.position_m))
            width = max(1, int(round(2 * DEFAULT_STADIUM.post_radius_m * camera.focal_px / depth)))
            for piece in _finite_pieces(uv, width_px, height_px):
                cv2.polylines(goal, [fixed_point(piece)], False, LINE_CLASSES.index(name) + 1, width,
                              cv2.LINE_8, 4)
        on_goal = (labels == SURFACE_GOAL) & (goal > 0)
        mask[on_goal] = goal[on_goal]
        return mask


def _reachable(points_px: np.ndarray, polyline_px: np.ndarray) -> np.ndarray:
    """The points within METRIC_REACH_PX of the metric's polyline of the class.

    Next to the image border the official metric replaces the marking by a chord from its
    last sample inside the image to a border point computed from the next (far) sample;
    a true point of the marking there can lie more than tau from that chord. Such points
    are dropped: the metric could not confirm them for any camera.
    """
    if not len(points_px):
        return points_px
    return points_px[distances_to_polyline(points_px, polyline_px) < METRIC_REACH_PX]


def _visible_vertices(polyline_px: np.ndarray, clear: np.ndarray) -> np.ndarray:
    """The metric polyline's vertices strictly inside the image whose pixel shows the marking."""
    height_px, width_px = clear.shape
    u, v = polyline_px[:, 0], polyline_px[:, 1]
    inside = (u > 0) & (u < width_px - 1) & (v > 0) & (v < height_px - 1)
    keep = inside.copy()
    keep[inside] = clear[np.rint(v[inside]).astype(int), np.rint(u[inside]).astype(int)]
    return polyline_px[keep]


def _unfolded(camera: Camera, points_w: np.ndarray) -> np.ndarray:
    """(N,) bool: the point is on the invertible branch of the k1 distortion.

    With k1 < 0, ``r (1 + k1 r^2)`` decreases beyond ``r = 1 / sqrt(3 |k1|)``: points that far
    off the optical axis are folded back into the image by the model, but no pixel sees them
    (the renderer inverts the first branch), so an annotator cannot mark them there.
    """
    points_c = camera.world_to_camera(points_w)
    depth = np.where(points_c[:, 2] > 1e-3, points_c[:, 2], np.nan)
    with np.errstate(invalid="ignore"):
        r2 = (points_c[:, 0] ** 2 + points_c[:, 1] ** 2) / depth**2
        if camera.k1 >= 0:
            return np.isfinite(r2)
        return r2 < 1.0 / (3.0 * -camera.k1)


def _finite_pieces(uv: np.ndarray, width_px: int, height_px: int, margin: float = 2000.0):
    """Runs of finite points near the image (to draw), each (K, 2)."""
    ok = np.isfinite(uv).all(axis=1)
    with np.errstate(invalid="ignore"):
        ok &= (uv[:, 0] > -margin) & (uv[:, 0] < width_px + margin) & (uv[:, 1] > -margin) & (uv[:, 1] < height_px + margin)
    for run in _runs(np.flatnonzero(ok)):
        if len(run) >= 2:
            yield uv[run]


def _runs(indices: np.ndarray) -> list[np.ndarray]:
    """Split sorted indices into runs of consecutive values."""
    if indices.size == 0:
        return []
    breaks = np.flatnonzero(np.diff(indices) > 1) + 1
    return np.split(indices, breaks)


def _pick_points(uv: np.ndarray, visible: np.ndarray, is_circle: bool) -> np.ndarray:
    """A few (K, 2) pixel points per visible piece, ends included, like a human annotator."""
    runs = _runs(np.flatnonzero(visible))
    pieces = []
    for run in runs:
        steps = np.linalg.norm(np.diff(uv[run], axis=0), axis=1)
        pieces.append((run, float(steps.sum())))
    long_enough = [p for p in pieces if p[1] >= MIN_PIECE_PX]
    if long_enough:
        pieces = long_enough
    chosen = []
    spacing = CIRCLE_POINT_SPACING_PX if is_circle else LINE_POINT_SPACING_PX
    for run, length in pieces:
        if len(run) == 1:
            chosen.append(uv[run])
            continue
        count = int(np.clip(np.ceil(length / spacing) + 1, 2, 24 if is_circle else 6))
        # Evenly spaced along the piece's pixel length.
        cumulative = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(uv[run], axis=0), axis=1))])
        targets = np.linspace(0.0, cumulative[-1], count)
        picks = np.unique(np.clip(np.searchsorted(cumulative, targets), 0, len(run) - 1))
        chosen.append(uv[run[picks]])
    return np.vstack(chosen) if chosen else np.zeros((0, 2))
