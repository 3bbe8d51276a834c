"""Domain randomisation of the field-model samples: a drawn :class:`~broadtrack_graph.synth.field_look.Look`
applied to the renderer's frame.

* :class:`GroundShader` is the renderer's background shader (``Renderer.render(background_shader=...)``):
  on the marking-free ground texture it recolours the grass (HSV), mows a stripe pattern, wears grass
  and paint, paints the markings at the look's width and colour from their distance field
  (:mod:`broadtrack_graph.synth.paint`), adds the coloured lines of other sports on artificial turf,
  lights the ground (floodlight pools, a hard shadow edge) and repaints boards and stands. It runs
  before goals and players are drawn, so they stand in front of all of it.
* :func:`tone_and_noise` and :func:`jpeg_round_trip` finish the image (global tone curve and white
  balance, sensor noise, JPEG artefacts).

Vectorised numpy / OpenCV over the rows that hold ground; smooth fields (wear, floodlights, stripe
fading) at a quarter of the resolution. Images are (H, W, 3) BGR uint8; X, Y (H, W) float32 metres in
the pitch frame. No I/O here.
"""

from __future__ import annotations

import math
from functools import lru_cache

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.synth.drawing import SURFACE_BOARD, SURFACE_GROUND, SURFACE_STAND
from broadtrack_graph.synth.field_look import Look
from broadtrack_graph.synth.paint import GroundGrid, Strokes, coverage, distance_field, lookup, marking_field

WORN_BGR = np.array([84.0, 124.0, 138.0], np.float32)
"""Colour of worn grass and bare soil (BGR)."""

TURF_PALETTE_BGR = ((30, 210, 240), (200, 120, 20), (40, 40, 200), (20, 130, 250), (230, 190, 90), (150, 60, 160))
"""Paint of other sports' lines on artificial turf: yellow, blue, red, orange, light blue, purple (BGR)."""

BOARDS_HALF_M = (57.0, 38.5)
"""Stripes are mown inside the boards (|x|, |y| metres)."""

DEFAULT_STRIPES = ("length", 105.0 / 18.0, 0.085, 6.0)
"""Pattern, width (m), contrast and sharpness of the texture's own stripes, used when the stripe switch is off."""

NOISE_TILE_SHAPE = (1120, 1984, 3)
"""Precomputed sensor noise (int8, 32 = one sigma) cropped at a random place per sample (fixed seed)."""


def hsv_adjust(image: np.ndarray, hue_shift: float, saturation: float, value: float) -> np.ndarray:
    """(H, W, 3) BGR uint8 with hue shifted (OpenCV units, 2 degrees) and saturation and value scaled."""
    i = np.arange(256, dtype=np.float32)
    lut = np.empty((1, 256, 3), np.uint8)
    lut[0, :, 0] = np.where(i < 180, np.mod(i + round(hue_shift), 180), i)
    lut[0, :, 1] = np.clip(i * saturation, 0, 255)
    lut[0, :, 2] = np.clip(i * value, 0, 255)
    return cv2.cvtColor(cv2.LUT(cv2.cvtColor(image, cv2.COLOR_BGR2HSV), lut), cv2.COLOR_HSV2BGR)


def _smooth_noise(rng: np.random.Generator, grid: GroundGrid, cell_m: float):
    """A smooth unit noise field over the ground grid's extent, as (values, x_min, y_min, cell) for :func:`_sample`."""
    rows = int(math.ceil(grid.rows * grid.texel_m / cell_m)) + 2
    cols = int(math.ceil(grid.cols * grid.texel_m / cell_m)) + 2
    return rng.standard_normal((rows, cols)).astype(np.float32), grid.x_min_m, grid.y_min_m, cell_m


def _sample(noise, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    values, x_min, y_min, cell = noise
    map_x = cv2.transform(x, np.array([[1.0 / cell, -x_min / cell]]))
    map_y = cv2.transform(y, np.array([[1.0 / cell, -y_min / cell]]))
    return cv2.remap(values, map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REFLECT)


def turf_strokes(rng: np.random.Generator) -> list[tuple[Strokes, tuple[int, int, int], float]]:
    """Lines of other sports on an artificial pitch: (strokes, BGR colour, half width m) per sport, 1 or 2 sports.

    Small-sided pitches across each half (touchlines along x = const, a halfway line, a centre circle and
    boxes), or cross lines every few metres over the width.
    """
    out = []
    colours = rng.permutation(len(TURF_PALETTE_BGR))
    for sport in range(int(rng.integers(1, 3))):
        segments, arcs = [], []
        if rng.random() < 0.6:
            half_len, half_wid = rng.uniform(22.0, 32.0), rng.uniform(13.0, 22.0)
            for side in (-1.0, 1.0):
                xc = side * rng.uniform(half_wid + 2.0, 51.0 - half_wid)
                x0, x1 = xc - half_wid, xc + half_wid
                segments += [[x0, -half_len, x0, half_len], [x1, -half_len, x1, half_len],
                             [x0, -half_len, x1, -half_len], [x0, half_len, x1, half_len], [x0, 0.0, x1, 0.0]]
                arcs.append([xc, 0.0, rng.uniform(4.0, 7.0), 0.0, 2 * math.pi])
                box = rng.uniform(5.0, 9.0)
                for end in (-1.0, 1.0):
                    y_goal, y_box = end * half_len, end * (half_len - rng.uniform(5.0, 9.0))
                    segments += [[xc - box, y_goal, xc - box, y_box], [xc + box, y_goal, xc + box, y_box],
                                 [xc - box, y_box, xc + box, y_box]]
        else:
            step = rng.uniform(4.5, 10.0)
            xs = np.arange(-50.0 + rng.uniform(0, step), 50.0, step)
            half = rng.uniform(20.0, 34.0)
            segments += [[x, -half, x, half] for x in xs]
        strokes = Strokes(np.asarray(segments, float).reshape(-1, 4), np.asarray(arcs, float).reshape(-1, 5),
                          np.zeros((0, 3)))
        out.append((strokes, TURF_PALETTE_BGR[int(colours[sport])], float(rng.uniform(0.04, 0.06))))
    return out


class GroundShader:
    """The renderer's background shader for one look (see the module docstring).

    Args:
        look: the sample's look.
        grid: the ground texture's grid (synth.paint.GroundGrid.of(textures)).
    """

    def __init__(self, look: Look, grid: GroundGrid) -> None:
        self.look = look
        self.grid = grid
        rng = np.random.default_rng([look.detail_seed, 31])
        self.coarse = _smooth_noise(rng, grid, 2.0)
        self.fine = _smooth_noise(rng, grid, 0.4)
        self.pools = np.column_stack([rng.uniform(-55, 55, 6), rng.uniform(-38, 38, 6), rng.uniform(12, 35, 6)])
        self.turf = turf_strokes(rng) if look.turf else []

    def __call__(self, camera: Camera, image: np.ndarray, labels: np.ndarray, X: np.ndarray, Y: np.ndarray) -> None:
        look = self.look
        for surface, hsv in ((SURFACE_BOARD, look.board_hsv), (SURFACE_STAND, look.crowd_hsv)):
            if hsv is not None:
                _recolour(image, labels == surface, hsv)
        ground = labels == SURFACE_GROUND
        rows = np.flatnonzero(ground.any(axis=1))
        if not rows.size:
            return
        band = slice(int(rows[0]), int(rows[-1]) + 1)
        img = image[band]
        x, y = np.clip(X[band], -300.0, 300.0), np.clip(Y[band], -300.0, 300.0)
        base = img if look.grass_hsv is None else hsv_adjust(img, *look.grass_hsv)
        inside = ground[band].astype(np.uint8)
        # One channel at a time (OpenCV on (H, W) float32 planes): grass, worn grass, then the layers on top.
        channels = [plane.astype(np.float32) for plane in cv2.split(base)]
        if look.turf:  # even, manufactured grass: half the natural variation
            mean = cv2.mean(base, inside)
            channels = [cv2.addWeighted(c, 0.5, c, 0.0, 0.5 * m) for c, m in zip(channels, mean)]
        wear, light, fade = self._smooth_fields(x, y, img.shape[:2])
        if wear is not None:
            kept = cv2.subtract(1.0, wear)
            channels = [cv2.scaleAdd(wear, float(worn), cv2.multiply(c, kept)) for c, worn in zip(channels, WORN_BGR)]
        if look.shadow is not None:
            light = cv2.multiply(light, _shadow(x, y, *look.shadow))
        # The frame is sum_k weight_k * colour_k: the grass under stripes, the markings, the turf lines on top,
        # all lit; each layer's alpha takes its share of what the layers above leave.
        map_x, map_y = self.grid.texel_coordinates(x, y)
        layers = [(coverage(lookup(marking_field(self.grid), map_x, map_y), look.line_half_width_m), look.line_bgr)]
        if look.wear > 0:
            worn = np.clip(1.0 - look.wear * (0.35 + 0.35 * _sample(self.fine, x, y)), 0.25, 1.0)
            cv2.multiply(layers[0][0], worn, dst=layers[0][0])
        for strokes, bgr, half_width in self.turf:
            layers.append((coverage(lookup(distance_field(self.grid, strokes), map_x, map_y), half_width), bgr))
        left = light  # the weight the layers above leave to the ones below
        weights = []
        for alpha, bgr in reversed(layers):
            weight = cv2.multiply(alpha, left)
            weights.append((weight, bgr))
            left = cv2.subtract(left, weight)
        left = cv2.multiply(left, self._stripes(x, y, fade))
        for c in range(3):
            channels[c] = cv2.multiply(channels[c], left)
            for weight, bgr in weights:
                channels[c] = cv2.scaleAdd(weight, float(bgr[c]), channels[c])
        cv2.copyTo(cv2.convertScaleAbs(cv2.merge(channels)), inside, img)

    def _smooth_fields(self, x, y, shape):
        """Worn-grass weight (or None), floodlight gain and stripe fading, each (H, W) float32 at the band's size."""
        look = self.look
        xs, ys = np.ascontiguousarray(x[::4, ::4]), np.ascontiguousarray(y[::4, ::4])
        # Footprint of a pixel on the ground (metres, its larger extent): stripes narrower than it fade out.
        fu = np.hypot(np.diff(xs, axis=1, append=xs[:, -1:]), np.diff(ys, axis=1, append=ys[:, -1:]))
        fv = np.hypot(np.diff(xs, axis=0, append=xs[-1:]), np.diff(ys, axis=0, append=ys[-1:]))
        width = look.stripe_width_m if look.stripe_pattern is not None else DEFAULT_STRIPES[1]
        fade = np.exp(-np.square(np.maximum(fu, fv) * (0.5 / width))).astype(np.float32)
        light = np.ones_like(xs)
        if look.floodlight > 0:
            pools = np.zeros_like(xs)
            for px, py, sigma in self.pools:
                np.maximum(pools, np.exp(-((xs - px) ** 2 + (ys - py) ** 2) / np.float32(2 * sigma * sigma)), out=pools)
            light = (1.0 + look.floodlight * (pools - 0.5)).astype(np.float32)
        wear = None
        if look.wear > 0:
            hot = np.zeros_like(xs)
            for cx, cy, sx, sy in ((-49.5, 0.0, 4.0, 6.0), (49.5, 0.0, 4.0, 6.0), (0.0, 0.0, 6.0, 6.0),
                                   (-41.5, 0.0, 2.5, 2.5), (41.5, 0.0, 2.5, 2.5)):
                hot += np.exp(-0.5 * (((xs - cx) / sx) ** 2 + ((ys - cy) / sy) ** 2))
            hot += 0.6 * np.exp(-0.5 * ((np.abs(ys) - 33.0) / 1.2) ** 2)  # the assistant referees' runs
            n = _sample(self.coarse, xs, ys)
            wear = np.clip(hot * (0.6 + 0.5 * n) + 0.3 * np.maximum(n - 0.8, 0.0), 0.0, 1.0)
            wear = (look.wear * wear).astype(np.float32)
        size = (shape[1], shape[0])
        up = [cv2.resize(a, size, interpolation=cv2.INTER_LINEAR) for a in (fade, light)]
        return (None if wear is None else cv2.resize(wear, size, interpolation=cv2.INTER_LINEAR)), up[1], up[0]

    def _stripes(self, x, y, fade) -> np.ndarray:
        """(H, W) float32 brightness factor of the mowing pattern (1 outside the boards)."""
        look = self.look
        if look.stripe_pattern is None:
            pattern, width, contrast, sharpness, phase = (*DEFAULT_STRIPES, 0.0)
        else:
            pattern, width, contrast = look.stripe_pattern, look.stripe_width_m, look.stripe_contrast
            sharpness, phase = look.stripe_sharpness, look.stripe_phase
        if pattern == "none" or contrast <= 0:
            return np.ones_like(x)
        k = np.float32(math.pi / width)

        def wave(t):  # +-1 square-ish wave of period 2 stripes
            steep = np.tanh(np.float32(sharpness) * np.sin(k * t + np.float32(math.pi * phase)))
            return steep / np.float32(math.tanh(sharpness))

        if pattern == "length":
            s = wave(x)
        elif pattern == "width":
            s = wave(y)
        elif pattern == "checker":
            s = wave(x) * wave(y)
        elif pattern == "diagonal":
            s = wave(np.float32(math.cos(look.stripe_angle_rad)) * x + np.float32(math.sin(look.stripe_angle_rad)) * y)
        else:  # circles
            s = wave(np.hypot(x, y))
        inside = (np.abs(x) <= BOARDS_HALF_M[0]) & (np.abs(y) <= BOARDS_HALF_M[1])
        return np.where(inside, 1.0 + np.float32(contrast) * s * fade, 1.0).astype(np.float32)


def _shadow(x, y, normal_rad: float, offset_m: float, darkness: float, penumbra_m: float) -> np.ndarray:
    """(H, W) float32 gain: 1 in the light, 1 - darkness in the shadow beyond a straight edge, soft over penumbra_m."""
    along = np.float32(math.cos(normal_rad)) * x + np.float32(math.sin(normal_rad)) * y
    shade = np.clip((along - np.float32(offset_m)) / np.float32(penumbra_m) + 0.5, 0.0, 1.0)
    return (1.0 - np.float32(darkness) * shade).astype(np.float32)


def _recolour(image: np.ndarray, mask: np.ndarray, hsv: tuple[float, float, float]) -> None:
    """Recolour the masked pixels of image in place (the rows that hold them)."""
    rows = np.flatnonzero(mask.any(axis=1))
    if rows.size:
        band = slice(int(rows[0]), int(rows[-1]) + 1)
        cv2.copyTo(hsv_adjust(image[band], *hsv), mask[band].astype(np.uint8), image[band])


@lru_cache(maxsize=1)
def noise_tile() -> np.ndarray:
    """The precomputed sensor noise (:data:`NOISE_TILE_SHAPE`, int8, 32 per sigma; fixed seed, built once)."""
    noise = np.random.default_rng(20240611).standard_normal(NOISE_TILE_SHAPE, dtype=np.float32) * 32.0
    tile = np.clip(np.rint(noise), -127, 127).astype(np.int8)
    tile.setflags(write=False)
    return tile


def tone_and_noise(image: np.ndarray, look: Look, rng: np.random.Generator) -> np.ndarray:
    """The whole image's tone curve and white balance, then sensor noise (a new array; image unchanged).

    Args:
        image: (H, W, 3) BGR uint8.
        look: tone (exposure, blue gain, red gain, gamma) and noise_sigma (grey levels).
        rng: where the noise crop is drawn.
    """
    out = image
    if look.tone is not None:
        exposure, blue, red, gamma = look.tone
        i = np.arange(256, dtype=np.float64) / 255.0
        lut = np.empty((1, 256, 3), np.uint8)
        for channel, gain in enumerate((blue, 1.0, red)):
            lut[0, :, channel] = np.clip(255.0 * np.clip(i * exposure * gain, 0.0, 1.0) ** gamma + 0.5, 0, 255)
        out = cv2.LUT(out, lut)
    if look.noise_sigma:
        H, W = out.shape[:2]
        tile = noise_tile()
        if H <= tile.shape[0] and W <= tile.shape[1]:
            oy, ox = int(rng.integers(tile.shape[0] - H + 1)), int(rng.integers(tile.shape[1] - W + 1))
            noise = tile[oy:oy + H, ox:ox + W]
        else:
            noise = np.clip(rng.standard_normal((H, W, 3), dtype=np.float32) * 32.0, -127, 127).astype(np.int8)
        out = cv2.addWeighted(out, 1.0, noise, look.noise_sigma / 32.0, 0.0, dtype=cv2.CV_8U)
    return out if out is not image else image.copy()


def jpeg_round_trip(image: np.ndarray, quality: int) -> np.ndarray:
    """(H, W, 3) BGR uint8 encoded as JPEG at quality (0..100, chroma subsampled 4:2:0) and decoded."""
    ok, data = cv2.imencode(".jpg", image, [cv2.IMWRITE_JPEG_QUALITY, int(np.clip(quality, 1, 100))])
    if not ok:
        raise ValueError(f"JPEG encoding failed at quality {quality}")
    return cv2.imdecode(data, cv2.IMREAD_COLOR)
