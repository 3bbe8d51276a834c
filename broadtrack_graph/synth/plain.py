"""A plain renderer of a pitch, written apart from the synthetic renderer (:mod:`.render`) to check the single-frame
calibrator on views it was not tuned on. No I/O.

It shares nothing with the main renderer but the camera model: the markings are drawn from the Laws of the Game's
dimensions written out here (105 x 68 m; the template of :mod:`broadtrack_graph.geometry.pitch` is not read), as
the distance of each pixel's ground point to the nearest marking's centre line, antialiased by that distance's
change ``s`` to the next pixel (paint covers the share of a pixel's box between the band's two edges,
``clip(0.5 + (w / 2 - d) / s, 0, 1) - clip(0.5 - (w / 2 + d) / s, 0, 1)``: a line far thinner than a pixel covers
``w / s`` of it); grass is mown
in stripes across the length; beyond the grass (the boards' line, 4.5 m outside the touchlines and goal lines) and
above the horizon a crowd of coloured blocks stands; players are upright coloured ellipses 1.8 m tall on the grass
near the view's aim; then a lens blur, a motion blur along a random direction, sensor noise and JPEG compression, each
drawn per frame (:func:`draw_plain_look`).

Conventions: pitch frame in metres, origin at the centre spot, z down (the camera's); images BGR uint8.
"""

from __future__ import annotations

from dataclasses import dataclass, replace

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera

HALF_LENGTH_M, HALF_WIDTH_M = 52.5, 34.0
CIRCLE_RADIUS_M = 9.15
PENALTY_DEPTH_M, PENALTY_HALF_WIDTH_M = 16.5, 20.16
GOAL_AREA_DEPTH_M, GOAL_AREA_HALF_WIDTH_M = 5.5, 9.16
PENALTY_SPOT_M = 11.0
CORNER_RADIUS_M = 1.0
SPOT_RADIUS_M = 0.11
GRASS_BEYOND_M = 4.5
"""Grass beyond the touchlines and goal lines, up to the boards."""

# One quarter of the markings (x >= 0, y >= 0); the pitch is symmetric about both axes.
_SEGMENTS_M = np.array([
    (0.0, HALF_WIDTH_M, HALF_LENGTH_M, HALF_WIDTH_M),  # touchline
    (HALF_LENGTH_M, 0.0, HALF_LENGTH_M, HALF_WIDTH_M),  # goal line
    (0.0, 0.0, 0.0, HALF_WIDTH_M),  # halfway line
    (HALF_LENGTH_M - PENALTY_DEPTH_M, 0.0, HALF_LENGTH_M - PENALTY_DEPTH_M, PENALTY_HALF_WIDTH_M),
    (HALF_LENGTH_M - PENALTY_DEPTH_M, PENALTY_HALF_WIDTH_M, HALF_LENGTH_M, PENALTY_HALF_WIDTH_M),
    (HALF_LENGTH_M - GOAL_AREA_DEPTH_M, 0.0, HALF_LENGTH_M - GOAL_AREA_DEPTH_M, GOAL_AREA_HALF_WIDTH_M),
    (HALF_LENGTH_M - GOAL_AREA_DEPTH_M, GOAL_AREA_HALF_WIDTH_M, HALF_LENGTH_M, GOAL_AREA_HALF_WIDTH_M),
])


@dataclass(frozen=True)
class PlainLook:
    """One frame's appearance. Colours BGR 0-255; lengths in metres or output pixels."""

    grass_bgr: tuple[float, float, float]
    stripe_m: float  # width of a mown stripe (along the length)
    stripe_contrast: float  # relative brightness between stripes
    line_width_m: float  # painted width (0: no paint)
    paint_bgr: tuple[float, float, float]
    crowd_block_px: int
    players: int
    lens_blur_px: float  # Gaussian sigma
    motion_blur_px: int  # length of a linear motion blur (0 or 1: none)
    motion_angle_deg: float
    noise_sigma: float
    jpeg_quality: int  # 0: none
    seed: int  # crowd, players, noise


def draw_plain_look(rng: np.random.Generator) -> PlainLook:
    """A random look: clean to worn broadcast grass, paint 10-12 cm of 75-100 % white, some frames blurred by a pan,
    noise of 1-5 grey levels, JPEG quality 30-95 on two frames in three."""
    green = rng.uniform(0.75, 1.2)
    blurred = rng.random() < 0.3
    return PlainLook(
        grass_bgr=(float(rng.uniform(35, 70) * green), float(rng.uniform(115, 160) * green),
                   float(rng.uniform(45, 95) * green)),
        stripe_m=float(rng.uniform(4.5, 7.0)), stripe_contrast=float(rng.uniform(0.0, 0.12)),
        line_width_m=float(rng.uniform(0.10, 0.12)), paint_bgr=(float(rng.uniform(190, 255)),) * 3,
        crowd_block_px=int(rng.integers(3, 9)), players=int(rng.integers(6, 20)),
        lens_blur_px=float(rng.uniform(0.3, 1.0)), motion_blur_px=int(rng.integers(5, 25)) if blurred else 0,
        motion_angle_deg=float(rng.uniform(0, 180)), noise_sigma=float(rng.uniform(1.0, 5.0)),
        jpeg_quality=int(rng.integers(30, 96)) if rng.random() < 2 / 3 else 0, seed=int(rng.integers(1 << 31)))


def unpainted(look: PlainLook) -> PlainLook:
    """The same look without paint (where the paint shows is where the two renders differ)."""
    return replace(look, line_width_m=0.0)


def marking_distance_m(x: np.ndarray, y: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance (metres) of ground points to the nearest marking's centre line (lines, circles, arcs; the spots as
    discs) and the unit normal (..., 2) of that marking there (across a line, along the radius of a circle): the
    direction in which the distance changes. x, y: arrays of one shape, metres."""
    ax, ay = np.abs(x), np.abs(y)
    best = np.full(ax.shape, np.inf)
    normal = np.zeros(ax.shape + (2,))

    def take(distance, nx, ny, where=True):
        closer = (distance < best) & where
        best[closer] = distance[closer]
        normal[closer, 0] = np.broadcast_to(nx, ax.shape)[closer]
        normal[closer, 1] = np.broadcast_to(ny, ax.shape)[closer]

    for x0, y0, x1, y1 in _SEGMENTS_M:
        dx, dy = x1 - x0, y1 - y0
        length = np.hypot(dx, dy)
        t = np.clip(((ax - x0) * dx + (ay - y0) * dy) / (length * length), 0.0, 1.0)
        take(np.hypot(ax - (x0 + t * dx), ay - (y0 + t * dy)), -dy / length, dx / length)
    spot = HALF_LENGTH_M - PENALTY_SPOT_M
    in_corner = (ax <= HALF_LENGTH_M) & (ay <= HALF_WIDTH_M)
    for cx, cy, radius, where in ((0.0, 0.0, CIRCLE_RADIUS_M, True),
                                  (spot, 0.0, CIRCLE_RADIUS_M, ax <= HALF_LENGTH_M - PENALTY_DEPTH_M),
                                  (HALF_LENGTH_M, HALF_WIDTH_M, CORNER_RADIUS_M, in_corner),
                                  (0.0, 0.0, 0.0, True), (spot, 0.0, 0.0, True)):  # radius 0: the spots
        r = np.maximum(np.hypot(ax - cx, ay - cy), 1e-9)
        distance = np.abs(r - radius) if radius > 0 else np.maximum(0.0, r - SPOT_RADIUS_M)
        take(distance, (ax - cx) / r, (ay - cy) / r, where)
    return best, normal


def _every_pixel(camera: Camera) -> np.ndarray:
    """(H * W, 2) the pixel coordinates of the camera's image, row by row."""
    us, vs = np.meshgrid(np.arange(camera.width_px, dtype=float), np.arange(camera.height_px, dtype=float))
    return np.column_stack([us.ravel(), vs.ravel()])


def ground_of_pixels(camera: Camera) -> tuple[np.ndarray, np.ndarray]:
    """(x, y): (H, W) metres where each pixel's ray meets the ground (inf where it does not)."""
    W, H = camera.width_px, camera.height_px
    ground, hits = camera.ground_intersection(_every_pixel(camera))
    return np.where(hits, ground[:, 0], np.inf).reshape(H, W), np.where(hits, ground[:, 1], np.inf).reshape(H, W)


def render_plain(camera: Camera, look: PlainLook, ground: tuple[np.ndarray, np.ndarray] | None = None,
                 frame: int = 0, players_around_m: np.ndarray | None = None,
                 crowd_camera: Camera | None = None) -> np.ndarray:
    """(H, W, 3) uint8 BGR image of the pitch through ``camera`` (at its own resolution) under ``look``; ``ground``:
    the camera's :func:`ground_of_pixels` when already computed (rendering one view twice, with and without paint).

    A clip's frames: ``frame`` > 0 draws the noise afresh (frame 0: the look's own), and ``players_around_m`` (2,),
    the ground point the players stand around (None: where the camera looks), keeps them where frame 0 put them
    while the camera moves, and ``crowd_camera``, frame 0's camera (it must stand where ``camera`` stands), keeps the
    crowd's blocks where frame 0 saw them while the camera turns (None: the blocks are laid out on this camera's
    image)."""
    rng = np.random.default_rng(look.seed)
    W, H = camera.width_px, camera.height_px
    x, y = ground if ground is not None else ground_of_pixels(camera)
    grass = (np.abs(x) <= HALF_LENGTH_M + GRASS_BEYOND_M) & (np.abs(y) <= HALF_WIDTH_M + GRASS_BEYOND_M)
    # The crowd: coloured blocks, darker than the grass.
    block = look.crowd_block_px
    blocks = ((H + block - 1) // block, (W + block - 1) // block)
    crowd = rng.uniform(25, 150, blocks + (1,)) + rng.normal(0.0, 25.0, blocks + (3,))
    if crowd_camera is None:
        image = np.kron(crowd, np.ones((block, block, 1)))[:H, :W]
    else:
        image = crowd[_crowd_blocks(camera, crowd_camera, block, blocks)]
    stripe = np.where(np.floor(np.where(grass, x, 0.0) / look.stripe_m) % 2 == 0, 1.0, 1.0 - look.stripe_contrast)
    image = np.where(grass[..., None], np.array(look.grass_bgr) * stripe[..., None], image)
    if look.line_width_m > 0:
        gx, gy = np.where(grass, x, 0.0), np.where(grass, y, 0.0)
        distance, normal = marking_distance_m(gx, gy)
        # The distance's change to the next pixel: the marking's normal (turned from the folded quarter back to the
        # point's) against the ground step of one pixel.
        nx, ny = normal[..., 0] * np.where(gx < 0, -1.0, 1.0), normal[..., 1] * np.where(gy < 0, -1.0, 1.0)
        change = np.zeros_like(distance)
        for axis in (1, 0):
            step_x = np.diff(gx, axis=axis, append=np.take(gx, [-1], axis=axis))
            step_y = np.diff(gy, axis=axis, append=np.take(gy, [-1], axis=axis))
            change += (nx * step_x + ny * step_y) ** 2
        change = np.sqrt(change)
        # A pixel's box over the band |d| <= half width: its share between the band's two edges.
        step = np.maximum(change, 1e-6)
        half = 0.5 * look.line_width_m
        cover = np.clip(0.5 + (half - distance) / step, 0.0, 1.0) - np.clip(0.5 - (half + distance) / step, 0.0, 1.0)
        cover[~grass] = 0.0
        image = image * (1.0 - cover[..., None]) + np.array(look.paint_bgr) * cover[..., None]
    image = _players(image, camera, rng, look.players, players_around_m)
    if look.lens_blur_px > 0:
        image = cv2.GaussianBlur(image, (0, 0), look.lens_blur_px)
    if look.motion_blur_px > 1:
        kernel = np.zeros((look.motion_blur_px, look.motion_blur_px), np.float32)
        kernel[look.motion_blur_px // 2, :] = 1.0 / look.motion_blur_px
        turn = cv2.getRotationMatrix2D(((look.motion_blur_px - 1) / 2, (look.motion_blur_px - 1) / 2),
                                       look.motion_angle_deg, 1.0)
        kernel = cv2.warpAffine(kernel, turn, kernel.shape[::-1])
        image = cv2.filter2D(image, -1, kernel / max(kernel.sum(), 1e-6))
    noise = rng if frame == 0 else np.random.default_rng([look.seed, frame])
    image = np.clip(image + noise.normal(0.0, look.noise_sigma, image.shape), 0, 255).astype(np.uint8)
    if look.jpeg_quality:
        image = cv2.imdecode(cv2.imencode(".jpg", image, [cv2.IMWRITE_JPEG_QUALITY, look.jpeg_quality])[1],
                             cv2.IMREAD_COLOR)
    return image


def _crowd_blocks(camera: Camera, crowd_camera: Camera, block_px: int, blocks: tuple[int, int]):
    """(rows, columns), each (H, W) int: the crowd block each pixel of ``camera`` sees, the blocks laid out
    ``block_px`` apart on ``crowd_camera``'s image (the same focal point) and repeated beyond it: a crowd far away
    that stays put in the world while the camera turns."""
    W, H = camera.width_px, camera.height_px
    rays_w = camera.backproject(_every_pixel(camera))
    uv, front = crowd_camera.project(crowd_camera.position_m + rays_w)
    uv = np.where(front[:, None], uv, 0.0)
    # A pixel's own block on crowd_camera's image: its index over the block size (0.5 in from its edge, so that a
    # pixel mapped onto itself up to rounding keeps its block).
    columns = np.floor((uv[:, 0] + 0.5) / block_px).astype(int) % blocks[1]
    rows = np.floor((uv[:, 1] + 0.5) / block_px).astype(int) % blocks[0]
    return rows.reshape(H, W), columns.reshape(H, W)


def players_centre_m(camera: Camera) -> np.ndarray:
    """(2,) the ground point the players of a view stand around: where the camera looks (the centre spot when its
    axis misses the ground)."""
    aim, hits = camera.ground_intersection(np.array([[camera.width_px / 2.0, camera.height_px / 2.0]]))
    return aim[0, :2] if hits[0] else np.zeros(2)


def _players(image: np.ndarray, camera: Camera, rng: np.random.Generator, count: int,
             around_m: np.ndarray | None = None) -> np.ndarray:
    """Upright ellipses 1.8 m tall in two teams' colours, standing on the pitch around ``around_m`` (None: where the
    camera looks)."""
    centre = players_centre_m(camera) if around_m is None else np.asarray(around_m, float)
    teams = rng.uniform(0, 255, (2, 3))
    out = np.ascontiguousarray(image)
    for _ in range(count):
        foot = np.array([*np.clip(centre + rng.normal(0.0, 12.0, 2), [-HALF_LENGTH_M, -HALF_WIDTH_M],
                                  [HALF_LENGTH_M, HALF_WIDTH_M]), 0.0])
        uv, front = camera.project(np.array([foot, foot - (0.0, 0.0, 1.8)]))
        if not front.all():
            continue
        height = float(np.linalg.norm(uv[1] - uv[0]))
        if not 2.0 <= height <= camera.height_px:
            continue
        middle = (uv[0] + uv[1]) / 2.0
        cv2.ellipse(out, (int(middle[0]), int(middle[1])), (max(1, int(height * 0.17)), max(1, int(height / 2))),
                    0.0, 0.0, 360.0, tuple(float(c) for c in teams[int(rng.integers(2))]), -1)
    return out
