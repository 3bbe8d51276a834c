"""Renderer of broadcast frames through the tracker's exact camera model: one frame per call.

Per frame: the background by ray casting (:mod:`broadtrack_graph.synth.ray_cast`), goals and
players on top (:mod:`broadtrack_graph.synth.objects`), then image formation here: a moving
shadow band and exposure drift, motion blur along the image motion between the previous and the
current camera, lens softness, vignetting and sensor noise; optionally a JPEG round trip.

Besides the BGR image, the renderer returns a per-pixel surface label (what the ray
hit) and, on request, the class id of the marking under each ground pixel: the
ground truth uses them to decide what an annotator can see. No I/O here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Callable

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.synth.drawing import SURFACE_GROUND
from broadtrack_graph.synth.objects import draw_objects
from broadtrack_graph.synth.ray_cast import ground_maps, pixel_rays, sample_ground, surroundings
from broadtrack_graph.synth.scene import DEFAULT_STADIUM, GoalPart, PlayerTrack, Stadium, goal_parts
from broadtrack_graph.synth.texture import TextureSet, build_textures

BackgroundShader = Callable[[Camera, np.ndarray, np.ndarray, np.ndarray, np.ndarray], None]
"""``shader(camera, image, labels, X, Y)``: changes the background of a frame in place before goals and players are
drawn. image: (H, W, 3) BGR uint8; labels: (H, W) uint8 surface labels (drawing.SURFACE_*); X, Y: (H, W) float32
metres, where each pixel's ray meets the ground plane (meaningful on SURFACE_GROUND pixels only)."""


@dataclass(frozen=True)
class RenderSettings:
    """Image formation effects (all can be turned off for exact tests)."""

    noise_sigma: float = 2.2  # sensor noise, grey levels (RMS)
    motion_blur: bool = True  # blur along the image motion from the previous camera
    shutter_fraction: float = 0.3  # exposure time / frame interval (sports cameras use short shutters)
    lens_blur_sigma_px: float = 0.55  # optical softness at 1920 px width (scaled with width)
    sharpen: float = 0.5  # broadcast detail enhancement (unsharp mask amount, sigma 1.2 px at 1920)
    vignetting: float = 0.18  # relative darkening in the corners
    shadow: bool = True  # moving stand shadow across the pitch
    exposure_drift: float = 0.04  # slow relative exposure change
    jpeg_quality: int | None = None  # in-memory JPEG round trip (None: none; files are JPEG anyway)
    players: bool = True
    goals: bool = True


EXACT_SETTINGS = RenderSettings(noise_sigma=0.0, motion_blur=False, lens_blur_sigma_px=0.0, vignetting=0.0,
                                shadow=False, exposure_drift=0.0, sharpen=0.0)
"""No image degradation: for tests that compare pixels with geometry."""


@dataclass
class RenderedFrame:
    """One rendered frame.

    image: (H, W, 3) BGR uint8.
    labels: (H, W) uint8 surface label per pixel (SURFACE_*).
    class_ids: (H, W) uint8, LINE_CLASSES index + 1 of the ground marking under each
        ground pixel (0 elsewhere), or None when not requested.
    player_boxes_px: (M, 5) [player index, x0, y0, x1, y1] pixels of the players in view.
    """

    image: np.ndarray
    labels: np.ndarray
    class_ids: np.ndarray | None
    player_boxes_px: np.ndarray


class Renderer:
    """Renders frames of one size; reuses textures, pixel grids and noise between frames.

    Args:
        width_px, height_px: image size.
        seed: seed of the textures, the lighting and the noise.
        settings: image formation effects.
        stadium: stadium geometry.
        textures: the textures to sample (default: those of the seed, :func:`build_textures`, texel 0.025 m from
            1280 px wide, 0.05 m below).
    """

    def __init__(self, width_px: int, height_px: int, seed: int = 0, settings: RenderSettings = RenderSettings(),
                 stadium: Stadium = DEFAULT_STADIUM, textures: TextureSet | None = None) -> None:
        if width_px < 16 or height_px < 16:
            raise ValueError(f"image size must be at least 16x16, got {width_px}x{height_px}")
        self.width_px, self.height_px = int(width_px), int(height_px)
        self.settings = settings
        self.stadium = stadium
        self.pitch = PitchTemplate()
        if textures is None:
            textures = build_textures(0.025 if width_px >= 1280 else 0.05, int(seed) % 4, stadium)
        self.textures: TextureSet = textures
        self.goal_parts: list[GoalPart] = goal_parts(self.pitch, stadium)
        self._u = np.arange(self.width_px, dtype=np.float32)
        self._v = np.arange(self.height_px, dtype=np.float32)
        rng = np.random.default_rng([int(seed), 4242])
        self._noise_margin = 32
        if settings.noise_sigma > 0:
            noise = rng.normal(0.0, settings.noise_sigma, size=(self.height_px + 32, self.width_px + 32, 3))
            self._noise_pos = np.clip(noise, 0, 255).astype(np.uint8)
            self._noise_neg = np.clip(-noise, 0, 255).astype(np.uint8)
        # Vignetting gain map (1 in the centre), as uint8 with 1.0 == 200.
        yy, xx = np.meshgrid((self._v - self.height_px / 2) / (self.height_px / 2),
                             (self._u - self.width_px / 2) / (self.width_px / 2), indexing="ij")
        self._vignette = (1.0 - settings.vignetting * 0.5 * (xx**2 + yy**2)).astype(np.float32)
        self._shadow_phase = rng.uniform(0, 2 * math.pi)
        self._shadow_base_m = rng.uniform(-30.0, -12.0)
        self._rng_seed = int(seed)

    def rays(self, camera: Camera) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """World directions (not unit) of every pixel's ray: three (H, W) float32 arrays."""
        camera = camera.rescaled(self.width_px, self.height_px)
        return pixel_rays(camera, self._u, self._v)

    # ----------------------------------------------------------------- whole frame

    def render(self, camera: Camera, players: PlayerTrack | None = None, frame_index: int = 0,
               previous_camera: Camera | None = None, want_class_ids: bool = False, time_s: float | None = None,
               background_shader: BackgroundShader | None = None) -> RenderedFrame:
        """Render one frame.

        Args:
            camera: the camera (rescaled to the renderer's size if needed; k1-only distortion).
            players: player track of the clip (positions of frame_index are drawn), or None.
            frame_index: index into the player track and the noise / lighting sequences.
            previous_camera: camera of the previous frame, for motion blur (None: no blur).
            want_class_ids: also return the marking class id under every ground pixel.
            time_s: clip time for the lighting (default frame_index / 25).
            background_shader: changes the background (ground, boards, stands) in place before goals and players
                are drawn (None: none).

        Returns:
            RenderedFrame.
        """
        camera = camera.rescaled(self.width_px, self.height_px)
        settings = self.settings
        H, W = self.height_px, self.width_px
        time_s = frame_index / 25.0 if time_s is None else time_s
        dx, dy, dz = self.rays(camera)
        X, Y, inv, inner, map_x, map_y = ground_maps(camera, dx, dy, dz, self.stadium, self.textures)
        image = sample_ground(camera, map_x, map_y, inv, dz, self.textures)
        labels = np.minimum(inner, np.uint8(SURFACE_GROUND))  # SURFACE_GROUND where inner, SURFACE_NONE elsewhere
        outer_rows = np.flatnonzero(inner.min(axis=1) == 0)
        if outer_rows.size:
            surroundings(camera, image, labels, int(outer_rows[0]), int(outer_rows[-1]) + 1, dx, dy, dz, X, Y,
                         self.stadium, self.textures)
        class_ids = None
        if want_class_ids:
            class_ids = cv2.remap(self.textures.class_ids, map_x, map_y, cv2.INTER_NEAREST,
                                  borderMode=cv2.BORDER_CONSTANT, borderValue=0)
            class_ids[labels != SURFACE_GROUND] = 0
        # Lighting on the ground: a stand shadow whose edge drifts slowly, soft over ~0.6 m.
        gain = None
        if settings.shadow:
            step = 4
            Xc, Yc = X[::step, ::step], Y[::step, ::step]
            edge = self._shadow_base_m + 4.0 * math.sin(0.05 * time_s + self._shadow_phase) + 0.12 * Xc
            shade = np.clip((edge - Yc) / 0.6 + 0.5, 0.0, 1.0)
            ground_c = labels[::step, ::step] == SURFACE_GROUND
            gain_c = np.where(ground_c, 1.0 - 0.42 * shade, 1.0).astype(np.float32)
            gain = cv2.resize(gain_c, (W, H), interpolation=cv2.INTER_LINEAR)
        if background_shader is not None:
            background_shader(camera, image, labels, X, Y)
        boxes = draw_objects(camera, image, labels, self.goal_parts if settings.goals else [],
                             players if settings.players else None, frame_index)
        # Image formation.
        if settings.motion_blur and previous_camera is not None:
            self._motion_blur(image, camera, previous_camera)
        if settings.lens_blur_sigma_px > 0:
            sigma = settings.lens_blur_sigma_px * W / 1920.0
            if sigma >= 0.25:
                cv2.GaussianBlur(image, (3, 3), sigma, dst=image)
        if settings.sharpen > 0:
            soft = cv2.GaussianBlur(image, (5, 5), max(0.6, 1.2 * W / 1920.0))
            cv2.addWeighted(image, 1.0 + settings.sharpen, soft, -settings.sharpen, 0.0, dst=image)
        exposure = 1.0 + settings.exposure_drift * math.sin(0.21 * time_s + 1.3 * self._shadow_phase)
        total = self._vignette * np.float32(exposure) if settings.vignetting > 0 or exposure != 1.0 else None
        if gain is not None:
            total = gain if total is None else cv2.multiply(total, gain)
        if total is not None:
            gain_u8 = np.clip(total * 200.0, 0, 255).astype(np.uint8)
            cv2.multiply(image, cv2.merge([gain_u8, gain_u8, gain_u8]), dst=image, scale=1.0 / 200.0)
        if settings.noise_sigma > 0:
            rng = np.random.default_rng([self._rng_seed, int(frame_index), 17])
            oy, ox = (int(v) for v in rng.integers(0, self._noise_margin, size=2))
            cv2.add(image, self._noise_pos[oy:oy + H, ox:ox + W], dst=image)
            oy, ox = (int(v) for v in rng.integers(0, self._noise_margin, size=2))
            cv2.subtract(image, self._noise_neg[oy:oy + H, ox:ox + W], dst=image)
        if settings.jpeg_quality is not None:
            ok, data = cv2.imencode(".jpg", image, [cv2.IMWRITE_JPEG_QUALITY, int(settings.jpeg_quality)])
            image = cv2.imdecode(data, cv2.IMREAD_COLOR)
        return RenderedFrame(image=image, labels=labels, class_ids=class_ids, player_boxes_px=boxes)

    def _motion_blur(self, image, camera: Camera, previous_camera: Camera) -> None:
        """Box blur along the mean image motion of the centre region between the two cameras."""
        W, H = self.width_px, self.height_px
        grid = np.array([[u, v] for u in (0.3 * W, 0.5 * W, 0.7 * W) for v in (0.3 * H, 0.5 * H, 0.7 * H)])
        rays = camera.backproject(grid)
        points = camera.position_m + rays * 60.0  # a point at the scene's typical distance along each ray
        if previous_camera.width_px != W:
            previous_camera = previous_camera.rescaled(W, H)
        uv_prev, front = previous_camera.project(points)
        if not front.all():
            return
        motion = np.nanmean(grid - uv_prev, axis=0) * self.settings.shutter_fraction
        kx, ky = int(round(abs(motion[0]))), int(round(abs(motion[1])))
        if kx >= 2 or ky >= 2:
            cv2.blur(image, (max(1, kx) | 1, max(1, ky) | 1), dst=image)
