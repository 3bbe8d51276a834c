"""Bird's-eye view: the pitch from above with the camera and the ground footprint of its image.

Top-down drawing convention: image column grows with pitch x (left goal on the
left), image row grows with pitch y (the near touchline, +y, at the bottom), as a
viewer behind the main camera sees it. No file I/O here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate

DEFAULT_FAR_M = 120.0
"""Horizontal distance from the camera at which the footprint is cut (rays above the horizon or nearly flat)."""

PITCH_GREEN_BGR = (60, 120, 40)
SURROUND_BGR = (40, 70, 30)
LINE_WHITE_BGR = (235, 235, 235)
FOOTPRINT_BGR = (0, 215, 255)
CAMERA_BGR = (40, 40, 230)


def camera_footprint_w(camera: Camera, far_m: float = DEFAULT_FAR_M, samples_per_edge: int = 24) -> np.ndarray:
    """Ground footprint of the image: the image border back-projected to the pitch plane z = 0.

    A border pixel whose ray meets the ground within ``far_m`` (horizontal distance
    from the focal point) gives its ground point; a ray above the horizon, or one that
    meets the ground farther away, is cut at ``far_m`` along its horizontal direction.

    Args:
        camera: the camera.
        far_m: cut distance, metres.
        samples_per_edge: border pixels per image edge (distortion bends the edges).

    Returns:
        (4 * samples_per_edge, 2) polygon (x, y) in metres, pitch frame, running
        around the image border (top edge left to right, right edge, bottom, left).
    """
    w, h = camera.width_px, camera.height_px
    t = np.linspace(0.0, 1.0, samples_per_edge, endpoint=False)
    top = np.stack([t * w, np.zeros_like(t)], axis=1)
    right = np.stack([np.full_like(t, w), t * h], axis=1)
    bottom = np.stack([(1 - t) * w, np.full_like(t, h)], axis=1)
    left = np.stack([np.zeros_like(t), (1 - t) * h], axis=1)
    border_px = np.vstack([top, right, bottom, left])
    rays_w = camera.backproject(border_px)
    centre = camera.position_m
    height_m = -centre[2]  # z points down: a camera above the pitch has z < 0
    horizontal = np.hypot(rays_w[:, 0], rays_w[:, 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        distance = height_m / rays_w[:, 2]  # along the ray, to z = 0
        ground_range = distance * horizontal
    hits = (rays_w[:, 2] > 1e-9) & (height_m > 0) & (ground_range <= far_m)
    direction_xy = rays_w[:, :2] / np.maximum(horizontal, 1e-12)[:, None]
    far_xy = centre[:2] + far_m * direction_xy
    hit_xy = centre[:2] + np.where(hits, distance, 0.0)[:, None] * rays_w[:, :2]
    return np.where(hits[:, None], hit_xy, far_xy)


@dataclass(frozen=True)
class BirdseyeView:
    """Mapping from pitch metres to the pixels of a top-down drawing.

    x_range_m, y_range_m: the pitch-frame window drawn (metres).
    pixels_per_m: scale.
    """

    x_range_m: tuple[float, float]
    y_range_m: tuple[float, float]
    pixels_per_m: float

    @property
    def size_px(self) -> tuple[int, int]:
        """(width, height) of the drawing."""
        return (
            int(math.ceil((self.x_range_m[1] - self.x_range_m[0]) * self.pixels_per_m)),
            int(math.ceil((self.y_range_m[1] - self.y_range_m[0]) * self.pixels_per_m)),
        )

    def to_px(self, xy_m: np.ndarray) -> np.ndarray:
        """(N, 2) pitch (x, y) metres -> (N, 2) drawing pixels (float)."""
        xy_m = np.asarray(xy_m, dtype=float).reshape(-1, 2)
        return np.stack(
            [(xy_m[:, 0] - self.x_range_m[0]) * self.pixels_per_m, (xy_m[:, 1] - self.y_range_m[0]) * self.pixels_per_m],
            axis=1,
        )

    @classmethod
    def fitting(
        cls,
        width_px: int,
        template: PitchTemplate | None = None,
        camera_positions_w: np.ndarray | None = None,
        margin_m: float = 5.0,
        max_camera_distance_m: float = 60.0,
    ) -> "BirdseyeView":
        """A view of the pitch plus margin, stretched to hold the camera positions given.

        Camera positions farther than ``max_camera_distance_m`` outside the pitch are
        not included (the marker is then drawn clamped to the border).

        Args:
            width_px: drawing width in pixels; the height follows the aspect ratio.
            camera_positions_w: (N, 3) or (N, 2) focal point positions to include, metres.
        """
        dims = (template or PitchTemplate()).dimensions
        half_l, half_w = dims.length_m / 2, dims.width_m / 2
        x0, x1, y0, y1 = -half_l - margin_m, half_l + margin_m, -half_w - margin_m, half_w + margin_m
        if camera_positions_w is not None and len(camera_positions_w):
            xy = np.asarray(camera_positions_w, dtype=float)[:, :2]
            xy = xy[np.all(np.isfinite(xy), axis=1)]
            near = xy[
                (np.abs(xy[:, 0]) < half_l + max_camera_distance_m) & (np.abs(xy[:, 1]) < half_w + max_camera_distance_m)
            ]
            if len(near):
                x0, x1 = min(x0, near[:, 0].min() - margin_m), max(x1, near[:, 0].max() + margin_m)
                y0, y1 = min(y0, near[:, 1].min() - margin_m), max(y1, near[:, 1].max() + margin_m)
        return cls((x0, x1), (y0, y1), width_px / (x1 - x0))


@lru_cache(maxsize=4)
def _pitch_background(view: BirdseyeView, template_key: tuple) -> np.ndarray:
    template = PitchTemplate() if not template_key else PitchTemplate(template_key[0])
    width, height = view.size_px
    canvas = np.empty((height, width, 3), dtype=np.uint8)
    canvas[:] = SURROUND_BGR
    outline = view.to_px(template.outline_w[:, :2])
    cv2.fillPoly(canvas, [np.round(outline * 16).astype(np.int32)], PITCH_GREEN_BGR, cv2.LINE_AA, shift=4)
    thickness = max(1, int(round(view.pixels_per_m * 0.25)))
    samples = template.sample_uniform(0.5)
    goal_depth_m = 2.0
    for name, points_w in samples.items():
        if not template.is_on_ground(name):
            continue
        polyline = view.to_px(points_w[:, :2])
        cv2.polylines(canvas, [np.round(polyline * 16).astype(np.int32)], False, LINE_WHITE_BGR, thickness, cv2.LINE_AA, shift=4)
    # Goals: a small box behind each goal line, between the posts.
    half_l = template.dimensions.length_m / 2
    post_y = template.dimensions.goal_width_m / 2
    for side in (-1.0, 1.0):
        box = np.array([
            [side * half_l, -post_y], [side * (half_l + goal_depth_m), -post_y],
            [side * (half_l + goal_depth_m), post_y], [side * half_l, post_y],
        ])
        cv2.polylines(canvas, [np.round(view.to_px(box) * 16).astype(np.int32)], False, LINE_WHITE_BGR, thickness,
                      cv2.LINE_AA, shift=4)
    canvas.setflags(write=False)
    return canvas


def draw_birdseye(
    camera: Camera | None,
    view: BirdseyeView | None = None,
    width_px: int = 400,
    template: PitchTemplate | None = None,
    footprint_bgr: tuple[int, int, int] = FOOTPRINT_BGR,
    far_m: float = DEFAULT_FAR_M,
) -> np.ndarray:
    """Top-down drawing of the pitch with the camera and its image footprint.

    Args:
        camera: the camera, or None (pitch only, with "no camera" written on it).
        view: the metre -> pixel mapping (default: :meth:`BirdseyeView.fitting` on this
            camera's position); pass one view for a whole video so the inset stays still.
        width_px: drawing width when no view is given.
        template: the pitch (default 105 x 68).
        footprint_bgr: colour of the footprint (e.g. the confidence colour).
        far_m: cut distance of the footprint, metres.

    Returns:
        (H, W, 3) uint8 BGR image.
    """
    if view is None:
        positions = None if camera is None else camera.position_m[None, :]
        view = BirdseyeView.fitting(width_px, template, positions)
    key = () if template is None else (template.dimensions,)
    canvas = _pitch_background(view, key).copy()
    height, width = canvas.shape[:2]
    if camera is None:
        cv2.putText(canvas, "no camera", (10, height - 12), cv2.FONT_HERSHEY_SIMPLEX, 0.5, (220, 220, 220), 1, cv2.LINE_AA)
        return canvas
    footprint = view.to_px(camera_footprint_w(camera, far_m))
    polygon = np.round(footprint * 16).astype(np.int32)
    layer = canvas.copy()
    cv2.fillPoly(layer, [polygon], footprint_bgr, cv2.LINE_AA, shift=4)
    cv2.addWeighted(layer, 0.35, canvas, 0.65, 0.0, dst=canvas)
    cv2.polylines(canvas, [polygon], True, footprint_bgr, max(1, width // 250), cv2.LINE_AA, shift=4)
    # Camera marker, clamped to the drawing, with the horizontal direction of the optical axis.
    centre_px = view.to_px(camera.position_m[:2])[0]
    clamped = np.clip(centre_px, [4, 4], [width - 5, height - 5])
    radius = max(3, width // 80)
    axis = camera.optical_axis_w[:2]
    norm = float(np.hypot(*axis))
    if norm > 1e-6:
        tip = clamped + axis / norm * radius * 4
        cv2.arrowedLine(canvas, tuple(int(v) for v in np.round(clamped)), tuple(int(v) for v in np.round(tip)),
                        CAMERA_BGR, max(1, radius // 2), cv2.LINE_AA, tipLength=0.35)
    cv2.circle(canvas, tuple(int(v) for v in np.round(clamped)), radius, CAMERA_BGR, -1, cv2.LINE_AA)
    if not np.allclose(clamped, centre_px, atol=0.5):
        cv2.circle(canvas, tuple(int(v) for v in np.round(clamped)), radius + 2, (255, 255, 255), 1, cv2.LINE_AA)
    return canvas


def place_inset(
    image_bgr: np.ndarray,
    inset_bgr: np.ndarray,
    corner: str = "top-right",
    width_fraction: float = 0.25,
    margin_px: int | None = None,
    alpha: float = 0.9,
) -> np.ndarray:
    """Blend a small picture into a corner of an image (in place; also returned).

    Args:
        image_bgr: (H, W, 3) uint8 frame, modified.
        inset_bgr: the picture, resized to ``width_fraction`` of the frame width.
        corner: "top-left", "top-right", "bottom-left" or "bottom-right".
        alpha: opacity of the inset.
    """
    if corner not in ("top-left", "top-right", "bottom-left", "bottom-right"):
        raise ValueError(f"corner must be top-left, top-right, bottom-left or bottom-right, got '{corner}'")
    height, width = image_bgr.shape[:2]
    margin = margin_px if margin_px is not None else max(4, width // 100)
    inset_w = max(8, min(int(round(width * width_fraction)), width - 2 * margin))
    inset_h = max(8, int(round(inset_bgr.shape[0] * inset_w / inset_bgr.shape[1])))
    inset_h = min(inset_h, height - 2 * margin)
    resized = cv2.resize(inset_bgr, (inset_w, inset_h), interpolation=cv2.INTER_AREA)
    x0 = margin if corner.endswith("left") else width - margin - inset_w
    y0 = margin if corner.startswith("top") else height - margin - inset_h
    region = image_bgr[y0:y0 + inset_h, x0:x0 + inset_w]
    cv2.addWeighted(resized, alpha, region, 1.0 - alpha, 0.0, dst=region)
    cv2.rectangle(image_bgr, (x0, y0), (x0 + inset_w - 1, y0 + inset_h - 1), (255, 255, 255), 1)
    return image_bgr
