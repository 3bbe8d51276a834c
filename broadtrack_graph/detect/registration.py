"""The predicted template registered on the frame's ridge points, and the points it puts off the pitch. No I/O.

The weight-free detector names a ridge point after the nearest projected marking within a gate as wide as the
predicted camera is uncertain (during a pan, tens of pixels). A marking the frame does not show (a far touchline
at a grazing angle) then takes whatever parallel structure lies beyond it within that gate: the boards' lower edge,
the lettering of a grass-green board. Its points pull the camera as much as the markings that are there.

Most of a prediction's error is a turn and a zoom of the camera about its focal point (a tripod's camera pans, tilts,
rolls and zooms; its focal point barely moves), which moves the whole template together. So it is measured first
(:func:`register_template`): each named point paired with the template sample it was named after (and paired again
once, half way), Gauss-Newton steps on the distances across the samples' lines (a point may lie anywhere along its
marking), Tukey weights on a scale re-measured every round from the residuals' median, each step lightly damped where
the points do not fix it. A turn and a zoom cannot stretch one part of the image against another, so a structure
beside one marking does not move the fit; what is left is the residual scale, how far the markings still lie from
the registered template.

Painted markings lie on the pitch or on its outer lines, never beyond them. :func:`off_the_pitch` takes each point
named after a touchline or a goal line back through the registration onto the ground and marks those beyond the
outline by more than a few residual scales (in metres there, which grow with the distance): the boards and what is
written on them.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.distortion import undistort_normalized
from broadtrack_graph.geometry.pitch import LINE_CLASSES, OUTER_LINES, PitchDimensions
from broadtrack_graph.geometry.template import ImageTemplate

if TYPE_CHECKING:  # a type only: the process that prepares the frames imports this module, and no scipy
    from scipy.spatial import cKDTree

IS_OUTER_CLASS = np.isin(np.arange(len(LINE_CLASSES)), [LINE_CLASSES.index(name) for name in OUTER_LINES])
"""(classes,) bool: the class index is one of the pitch's outer lines."""

TUKEY_C = 4.685
"""Tukey's biweight constant, in residual scales (95 % efficiency on Gaussian residuals)."""

REPAIR_PX = 1.0
"""A registration step that moves the template more than this (pixels) pairs the points again."""

SETTLED_PX = 0.5
"""A registration step that moves the template less than this (pixels) ends the rounds."""


@dataclass(frozen=True)
class Registration:
    """The predicted camera turned and zoomed about its focal point so that its template lies on the ridge points.

    rotation: (3, 3) the turn, applied to the camera's rays (camera frame: x right, y down, z along the axis).
    focal_px: the zoomed focal length; centre_px: (2,) the principal point; predicted_focal_px: the prediction's.
    scale_px: robust scale of the registered residuals (pixels, 1.4826 times their median).
    """

    rotation: np.ndarray
    focal_px: float
    centre_px: np.ndarray
    predicted_focal_px: float
    scale_px: float

    def apply(self, uv_px: np.ndarray) -> np.ndarray:
        """(M, 2) predicted-template pixels where the registered camera draws them."""
        return _turned(uv_px, self.rotation, self.predicted_focal_px, self.focal_px, self.centre_px)

    def back(self, uv_px: np.ndarray) -> np.ndarray:
        """(M, 2) image pixels taken back to where the predicted camera draws the same ray (the inverse of apply)."""
        return _turned(uv_px, self.rotation.T, self.focal_px, self.predicted_focal_px, self.centre_px)


def _turned(uv_px: np.ndarray, rotation: np.ndarray, from_focal_px: float, to_focal_px: float, centre_px: np.ndarray
            ) -> np.ndarray:
    """Pixels of a pinhole camera (focal from_focal_px) moved to those of the same camera turned by rotation (applied
    to the rays) with focal to_focal_px; the principal point stays."""
    uv = np.asarray(uv_px, float).reshape(-1, 2)
    rays = np.column_stack([(uv - centre_px) / from_focal_px, np.ones(len(uv))])
    turned = rays @ rotation.T
    return centre_px + to_focal_px * turned[:, :2] / turned[:, 2:3]


def template_normals(template_uv: np.ndarray, index: np.ndarray, spacing_px: float) -> np.ndarray:
    """(K, 2) unit normals of the projected template at its samples ``index``, from their neighbours in the array (the
    samples of a densified piece follow each other about ``spacing_px`` apart); zero where a sample has no neighbour
    that close (a piece's lone sample).

    Args:
        template_uv: (M, 2) samples in their order along the template's pieces (pixels).
        index: (K,) the samples asked.
    """
    uv = np.asarray(template_uv, float).reshape(-1, 2)
    index = np.asarray(index, int)
    tangent = np.zeros((len(index), 2))
    at = uv[index]
    for side, beside in ((-1, np.maximum(index - 1, 0)), (1, np.minimum(index + 1, len(uv) - 1))):
        step = side * (uv[beside] - at)
        step[np.einsum("ij,ij->i", step, step) > (3.0 * spacing_px) ** 2] = 0.0  # a jump to the next piece
        tangent += step
    norm = np.sqrt(np.einsum("ij,ij->i", tangent, tangent))
    normals = np.zeros_like(tangent)
    has = norm > 0
    normals[has, 0], normals[has, 1] = -tangent[has, 1] / norm[has], tangent[has, 0] / norm[has]
    return normals


def register_template(template_uv: np.ndarray, points_px: np.ndarray, nearest: np.ndarray, focal_px: float,
                      centre_px, spacing_px: float, tree: cKDTree | None = None, gate_px: float = np.inf,
                      rounds: int = 6, min_points: int = 30, max_points: int = 150,
                      damping: float = 0.01) -> Registration | None:
    """The turn and zoom of the predicted camera that lay its template on the ridge points (module docstring), or None
    when fewer than ``min_points`` points are paired with a template sample that has a direction.

    Each point starts paired with the template sample it was named after (its nearest within the naming gate); each
    round makes one Gauss-Newton step on the distances across the samples' lines (point to line: a point may lie
    anywhere along its marking), Tukey-weighted on a scale re-measured every round from the residuals' median. Given
    the template's k-d tree, the points are paired again after a step that moved the template more than
    :data:`REPAIR_PX` (a prediction many pixels off pairs some points near corners with the wrong marking); the
    rounds stop once a step moves it less than :data:`SETTLED_PX`.

    Args:
        template_uv: (M, 2) the predicted camera's template samples (pixels), in their order along its pieces, about
            ``spacing_px`` apart.
        points_px: (N, 2) named ridge points (pixels); nearest: (N,) their samples. At most ``max_points`` of them,
            evenly spread, are used.
        focal_px, centre_px: the predicted camera's focal length and (2,) principal point, in these pixels.
        tree, gate_px: k-d tree of ``template_uv`` and the pairing distance, to pair the points again.
        damping: weight (in points) holding each step back (so that one straight marking leaves the turns it does not
            fix alone).
    """
    points, nearest = np.asarray(points_px, float).reshape(-1, 2), np.asarray(nearest, int)
    if len(points) > max_points:
        pick = np.linspace(0, len(points) - 1, max_points).astype(int)
        points, nearest = points[pick], nearest[pick]
    template_uv = np.asarray(template_uv, float).reshape(-1, 2)
    centre = np.asarray(centre_px, float)
    rotation, focal, moved_px = np.eye(3), float(focal_px), 0.0
    for round_index in range(rounds):
        if round_index == 0 or (tree is not None and moved_px > REPAIR_PX):
            if round_index:
                distance, nearest = tree.query(_turned(points, rotation.T, focal, focal_px, centre),
                                               distance_upper_bound=gate_px)
                nearest = np.where(np.isfinite(distance), nearest, -1)
            n = template_normals(template_uv, np.maximum(nearest, 0), spacing_px)
            has = n.any(axis=1) & (nearest >= 0)
            q, n, p = template_uv[nearest[has]], n[has], points[has]
            if len(p) < min_points:
                return None
        m = _turned(q, rotation, focal_px, focal, centre)  # a small turn keeps the samples' normals
        residual = np.einsum("ij,ij->i", n, p - m)
        scale = max(1.4826 * float(np.median(np.abs(residual))), 0.25)
        u = np.abs(residual) / (TUKEY_C * scale)
        weight = np.where(u < 1.0, (1.0 - u * u) ** 2, 0.0)
        # Image motion of a small turn (ax, ay, az, applied to the rays) and zoom z at normalised (x, y):
        # du = F (-x y ax + (1 + x^2) ay - y az + x z), dv = F (-(1 + y^2) ax + x y ay + x az + y z).
        x, y = ((m - centre) / focal).T
        nx, ny = n[:, 0], n[:, 1]
        design = focal * np.column_stack([-nx * x * y - ny * (1.0 + y * y), nx * (1.0 + x * x) + ny * x * y,
                                          -nx * y + ny * x, nx * x + ny * y])
        weighted = design * weight[:, None]
        step = np.linalg.solve(design.T @ weighted + damping * focal * focal * np.eye(4), weighted.T @ residual)
        rotation = cv2.Rodrigues(step[:3])[0] @ rotation
        focal *= 1.0 + step[3]
        moved_px = focal * float(np.max(np.abs(step)))  # about how far the step moved the template
        if moved_px < SETTLED_PX:
            break
    return Registration(rotation, focal, centre, float(focal_px), scale)


def off_the_pitch(points_px: np.ndarray, registration: Registration, camera: Camera, half_length_m: float,
                  half_width_m: float, margin_px) -> np.ndarray:
    """(N,) bool: the points that lie beyond the pitch's outer lines by more than ``margin_px`` (module docstring).

    Each point is taken back through the registration to the predicted camera's pixels and onto the ground; the
    margin in metres is the ground distance, along each of the pitch's axes, that ``margin_px`` pixels cover around
    the point (the most of four shifts, up, down, left and right, made on the undistorted image: the lens bends a
    few pixels by well under a pixel). A point whose ray misses the ground (above the horizon) is off the pitch.

    Args:
        points_px: (N, 2) pixels of ``camera`` (the predicted camera, at the points' image size).
        half_length_m, half_width_m: half the pitch's length (goal line: |x|) and width (touchline: |y|), metres.
        margin_px: pixels, one for all points or (N,) one each.
    """
    back = registration.back(points_px)
    undistorted = undistort_normalized((back - camera.principal_point) / camera.focal_px, camera.k1,
                                       camera.extra_distortion)
    directions = np.array([[0.0, 0.0], [1.0, 0.0], [-1.0, 0.0], [0.0, 1.0], [0.0, -1.0]])
    margin = np.broadcast_to(np.asarray(margin_px, float), (len(back),)) / camera.focal_px
    shifted = undistorted[:, None, :] + directions[None] * margin[:, None, None]  # (N, 5, 2)
    rays = np.concatenate([shifted, np.ones(shifted.shape[:2] + (1,))], axis=2) @ camera.R_cw  # world directions
    with np.errstate(divide="ignore", invalid="ignore"):
        along = -camera.position_m[2] / rays[..., 2]  # to the ground, z = 0
        hits = np.isfinite(along) & (along > 0)
        ground = camera.position_m[:2] + rays[..., :2] * along[..., None]
        spread = np.abs(ground[:, 1:] - ground[:, :1])  # (N, 4, 2); a shift off the ground: no bound
        reach = np.where(hits[:, 1:, None], spread, np.inf).max(axis=1)
        beyond = (np.abs(ground[:, 0, 0]) - half_length_m > reach[:, 0]) | \
            (np.abs(ground[:, 0, 1]) - half_width_m > reach[:, 1])
    return ~hits[:, 0] | beyond


def named_off_the_pitch(template: ImageTemplate, tree: cKDTree, points_px: np.ndarray, distance: np.ndarray,
                        nearest: np.ndarray, gate_px: float, camera: Camera, dimensions: PitchDimensions,
                        spacing_px: float, base_px: float, sigmas: float) -> np.ndarray:
    """(N,) bool: the named points beyond the pitch's outer lines by more than ``base_px + sigmas`` residual scales
    and half their marking's width, once the template is registered on the named points (:func:`register_template`,
    :func:`off_the_pitch`); all False when it cannot be.

    Only the points named after an outer line are asked (a point beyond the outline lies nearest to one of them), and
    of those only the ones that lie beyond their line in the image by half the margin, across it and away from the
    other visible markings (the outline is convex and holds them all), are taken to the ground.

    Args:
        template: the predicted camera's template samples that can be named after, spacing_px apart along their
            pieces; tree: their k-d tree.
        points_px, distance, nearest: the points and their nearest sample within the naming gate gate_px (distance
            inf: not named), as ``tree.query`` returns them.
        camera: the predicted camera at the points' image size.
    """
    off = np.zeros(len(points_px), bool)
    uv, classes = template.uv_px, template.class_index
    named = np.flatnonzero(np.isfinite(distance))
    outer = named[IS_OUTER_CLASS[classes[nearest[named]]]]
    if not len(outer):
        return off
    registered = register_template(uv, points_px[named], nearest[named], camera.focal_px, camera.principal_point,
                                   spacing_px, tree, gate_px)
    if registered is None:
        return off
    sample = nearest[outer]
    margin = base_px + sigmas * registered.scale_px + 0.5 * template.width_m_px[sample]
    moved = registered.apply(uv[sample])
    # Across its line a point can be no farther from where the registration moved its sample than its distance to
    # the sample plus the move: the others are not asked.
    near = distance[outer] + np.linalg.norm(moved - uv[sample], axis=1) > 0.5 * margin
    outer, sample, margin, moved = outer[near], sample[near], margin[near], moved[near]
    normal = template_normals(uv, sample, spacing_px)
    # The inner side of each outer line: towards the centroid of the other visible markings (one per class).
    sums = np.column_stack([np.bincount(classes, uv[:, k], len(LINE_CLASSES)) for k in (0, 1)])
    counts = np.bincount(classes, minlength=len(LINE_CLASSES)).astype(float)
    others = counts.sum() - counts
    inside = registered.apply((sums.sum(axis=0) - sums) / np.maximum(others, 1.0)[:, None])
    own = classes[sample]
    across = np.einsum("ij,ij->i", normal, points_px[outer] - moved)
    outward = np.einsum("ij,ij->i", normal, moved - inside[own])
    asked = (others[own] > 0) & (np.sign(outward) * across > 0.5 * margin)
    if asked.any():
        off[outer[asked]] = off_the_pitch(points_px[outer[asked]], registered, camera, dimensions.length_m / 2,
                                          dimensions.width_m / 2, margin[asked])
    return off
