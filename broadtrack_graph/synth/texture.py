"""Precomputed textures of the synthetic stadium: grass and markings, boards, stands.

All textures are BGR uint8 images sampled by the renderer with ``cv2.remap``:

* ground: a top-down image of the pitch and its surround (up to the foot of the
  stands), ``texel_m`` metres per texel, texel (col, row) centred at
  ``(x_min + (col + 0.5) texel, y_min + (row + 0.5) texel)``; mowing stripes,
  multi-scale grass texture, worn areas, 12 cm markings with wear; plus a pyramid
  (each level half the resolution) against aliasing, and a class-id texture
  (class index + 1 of LINE_CLASSES under each texel, 0 elsewhere) for the masks.
* boards: an atlas of the four board sides (far, near, left, right), each
  ``board_rows`` rows (top row at the top of the boards) by ``board_cols``.
* stands: an atlas of the four stand sides, rows from the top of the stands down
  to their foot, columns along the side (extended beyond the corners).

Everything is generated from a seed, deterministically. No I/O here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import cv2
import numpy as np

from broadtrack_graph.geometry.pitch import LINE_CLASSES, PitchTemplate
from broadtrack_graph.synth.scene import DEFAULT_STADIUM, Stadium

GRASS_BGR = np.array([72.0, 172.0, 118.0], dtype=np.float32)
LINE_BGR = np.array([232.0, 240.0, 238.0], dtype=np.float32)
TRACK_BGR = np.array([112.0, 118.0, 160.0], dtype=np.float32)
BRANDS = ("NORDA", "VELTRO", "KAPPEX", "SOLIS BANK", "ORBIT AIR", "FENTA", "MERIDIAN", "ZAPCOM",
          "LUMEX TV", "GRANITE", "PULSAR", "AQUAVIVA", "TRAXO", "HELIOS", "QUBIT", "ALTAMAR")
SIDES = ("far", "near", "left", "right")  # y = -h, y = +h, x = -h, x = +h


@dataclass(frozen=True)
class TextureSet:
    """Textures and their placement (see module docstring)."""

    texel_m: float
    x_min_m: float
    y_min_m: float
    ground_levels: tuple  # BGR uint8 pyramids, level k has texel texel_m * 2**k
    class_ids: np.ndarray  # (rows, cols) uint8 at level 0
    boards: np.ndarray  # (4 * board_rows, board_cols, 3) uint8
    board_texel_m: float
    board_rows: int
    board_u_min_m: float  # u (metres along a side) of column 0's left edge
    stands: np.ndarray  # (4 * stand_rows, stand_cols, 3) uint8
    stand_texel_m: float
    stand_rows: int
    stand_u_min_m: float


def _noise(shape: tuple[int, int], cells: tuple[int, int], rng: np.random.Generator) -> np.ndarray:
    """Smooth zero-mean noise of unit-ish amplitude: random (cells) grid upsampled (cubic) to shape."""
    small = rng.standard_normal((max(int(cells[0]), 2), max(int(cells[1]), 2))).astype(np.float32)
    return cv2.resize(small, (shape[1], shape[0]), interpolation=cv2.INTER_CUBIC)


def _world_to_texel(points_xy: np.ndarray, x_min: float, y_min: float, texel: float) -> np.ndarray:
    return np.column_stack([(points_xy[:, 0] - x_min) / texel - 0.5, (points_xy[:, 1] - y_min) / texel - 0.5])


def _draw_polyline(image: np.ndarray, points_px: np.ndarray, value: int, thickness: float, antialiased: bool = True) -> None:
    shift = 4
    pts = np.round(points_px * (1 << shift)).astype(np.int32).reshape(-1, 1, 2)
    line_type = cv2.LINE_AA if antialiased else cv2.LINE_8
    cv2.polylines(image, [pts], False, int(value), max(1, int(round(thickness))), line_type, shift)


def _ground(pitch: PitchTemplate, stadium: Stadium, texel: float, rng: np.random.Generator, markings: bool = True,
            stripes: bool = True):
    x_min, y_min = -stadium.stand_half_x_m, -stadium.stand_half_y_m
    cols = int(math.ceil(2 * stadium.stand_half_x_m / texel))
    rows = int(math.ceil(2 * stadium.stand_half_y_m / texel))
    xs = x_min + (np.arange(cols, dtype=np.float32) + 0.5) * texel
    ys = y_min + (np.arange(rows, dtype=np.float32) + 0.5) * texel
    d = pitch.dimensions
    half_l, half_w = d.length_m / 2, d.width_m / 2

    # Mowing stripes across the length (bands in x), soft edges; a fainter cross pattern.
    stripe_w = d.length_m / 18.0
    phase = (xs + half_l) / stripe_w
    stripe_x = 1.0 + (0.085 if stripes else 0.0) * np.tanh(6.0 * np.sin(math.pi * phase)).astype(np.float32)
    cross_w = d.width_m / 10.0
    cross = np.tanh(6.0 * np.sin(math.pi * (ys + half_w) / cross_w)).astype(np.float32)
    stripe_y = 1.0 + (0.012 if stripes else 0.0) * cross
    brightness = stripe_y[:, None] * stripe_x[None, :]
    # Multi-scale texture: patches (metres), clumps (decimetres), blades (texel grain).
    brightness *= 1.0 + 0.03 * _noise((rows, cols), (rows * texel // 6 + 2, cols * texel // 6 + 2), rng)
    brightness *= 1.0 + 0.03 * _noise((rows, cols), (int(rows * texel / 0.6), int(cols * texel / 0.6)), rng)
    grain = rng.standard_normal((rows, cols), dtype=np.float32)
    grain = cv2.GaussianBlur(grain, (0, 0), 0.7)
    brightness *= 1.0 + 0.08 * grain
    hue = _noise((rows, cols), (int(rows * texel / 3) + 2, int(cols * texel / 3) + 2), rng)

    # Worn, browner areas in the goal mouths and the centre.
    wear = np.zeros((rows, cols), dtype=np.float32)
    for cx, cy, sx, sy in ((-half_l + 3.0, 0.0, 4.0, 5.0), (half_l - 3.0, 0.0, 4.0, 5.0), (0.0, 0.0, 6.0, 6.0)):
        # Separable Gaussian blob, computed in its own window (3.5 sigma).
        c0, c1 = np.searchsorted(xs, [cx - 3.5 * sx, cx + 3.5 * sx])
        r0, r1 = np.searchsorted(ys, [cy - 3.5 * sy, cy + 3.5 * sy])
        gx = np.exp(-0.5 * ((xs[c0:c1] - cx) / sx) ** 2).astype(np.float32)
        gy = np.exp(-0.5 * ((ys[r0:r1] - cy) / sy) ** 2).astype(np.float32)
        wear[r0:r1, c0:c1] += 0.55 * np.outer(gy, gx)
    wear *= np.clip(1.0 + 0.8 * _noise((rows, cols), (int(rows * texel / 1.5), int(cols * texel / 1.5)), rng), 0, 2)
    np.clip(wear, 0.0, 1.0, out=wear)

    # Markings: 12 cm wide, antialiased, with wear and gaps.
    class_ids = np.zeros((rows, cols), dtype=np.uint8)
    paint = np.zeros((rows, cols), dtype=np.uint8)
    width_texels = stadium.line_width_m / texel
    samples = pitch.sample_uniform(0.05)
    for index, name in enumerate(LINE_CLASSES):
        if not pitch.is_on_ground(name):
            continue
        pts = _world_to_texel(samples[name][:, :2], x_min, y_min, texel)
        _draw_polyline(paint, pts, 255, width_texels)
        _draw_polyline(class_ids, pts, index + 1, width_texels, antialiased=False)
    spots = [pitch.keypoints["Centre spot"], pitch.keypoints["Left penalty mark"], pitch.keypoints["Right penalty mark"]]
    for spot in spots:
        centre = _world_to_texel(spot[None, :2], x_min, y_min, texel)[0]
        cv2.circle(paint, tuple(np.round(centre * 16).astype(int)), int(round(0.11 / texel * 16)), 255, -1, cv2.LINE_AA, 4)
    for sx in (-1, 1):  # corner arcs (not a SoccerNet class, but on every pitch)
        for sy in (-1, 1):
            angles = np.linspace(0, math.pi / 2, 24)
            arc = np.column_stack([sx * (half_l - np.cos(angles)), sy * (half_w - np.sin(angles))])
            _draw_polyline(paint, _world_to_texel(arc, x_min, y_min, texel), 255, width_texels)
    alpha = paint.astype(np.float32)
    alpha *= np.float32(1.0 / 255.0)
    del paint
    line_wear = 0.86 + 0.1 * _noise((rows, cols), (int(rows * texel / 0.4), int(cols * texel / 0.4)), rng)
    line_wear -= 0.22 * np.clip(_noise((rows, cols), (int(rows * texel / 2.0), int(cols * texel / 2.0)), rng) - 0.8, 0, 1)
    line_wear += 0.05 * grain
    alpha *= np.clip(line_wear, 0.45, 1.0, out=line_wear)
    del line_wear
    if not markings:  # the random stream is drawn all the same: boards and stands stay those of the seed
        alpha[:] = 0.0

    # Colour, one channel at a time (memory): grass, worn areas, track outside the boards, paint.
    outside = ~((np.abs(xs)[None, :] <= stadium.board_half_x_m) & (np.abs(ys)[:, None] <= stadium.board_half_y_m))
    track = 1.0 + 0.04 * grain[outside]
    del grain
    worn_bgr = np.array([92.0, 140.0, 128.0], dtype=np.float32)
    ground = np.empty((rows, cols, 3), dtype=np.uint8)
    for c in range(3):
        colour = GRASS_BGR[c] * (1.0 + (0.06 if c == 0 else -0.02 if c == 1 else 0.03) * hue)
        colour += wear * (worn_bgr[c] - colour)
        colour *= brightness
        colour[outside] = TRACK_BGR[c] * track
        colour += alpha * (LINE_BGR[c] - colour)
        ground[..., c] = np.clip(colour, 0, 255)
        del colour
    levels = [ground]
    while min(levels[-1].shape[:2]) > 64 and len(levels) < 7:
        levels.append(cv2.pyrDown(levels[-1]))
    return tuple(levels), class_ids, x_min, y_min


def _boards(stadium: Stadium, texel: float, rng: np.random.Generator):
    rows = int(math.ceil(stadium.board_height_m / texel))
    u_min = -max(stadium.board_half_x_m, stadium.board_half_y_m)
    cols = int(math.ceil(-2 * u_min / texel))
    atlas = np.zeros((4 * rows, cols, 3), dtype=np.uint8)
    for side in range(4):
        strip = atlas[side * rows:(side + 1) * rows]
        u = 0.0
        while u < cols * texel:
            length = rng.uniform(6.0, 14.0)
            c0, c1 = int(u / texel), min(cols, int((u + length) / texel))
            background = rng.integers(0, 256, size=3)
            if rng.random() < 0.5:
                background = (background * 0.35).astype(int)  # dark LED panel
            text_colour = (255 - background).clip(0, 255)
            if np.abs(text_colour.astype(int) - background).sum() < 200:
                text_colour = np.array([255, 255, 255]) if background.sum() < 380 else np.array([20, 20, 20])
            strip[:, c0:c1] = background
            word = BRANDS[int(rng.integers(len(BRANDS)))]
            scale = rows / 34.0
            thickness = max(1, int(rows / 12))
            (tw, th), _ = cv2.getTextSize(word, cv2.FONT_HERSHEY_DUPLEX, scale, thickness)
            x = c0 + max(0, ((c1 - c0) - tw) // 2)
            cv2.putText(strip, word, (x, (rows + th) // 2), cv2.FONT_HERSHEY_DUPLEX, scale, tuple(int(v) for v in text_colour),
                        thickness, cv2.LINE_AA)
            strip[:, c0:c0 + 1] = 30  # gap between boards
            u += length
        strip[:2] = 40  # top edge
    return atlas, rows, u_min


def _stands(stadium: Stadium, texel: float, rng: np.random.Generator):
    rows = int(math.ceil(stadium.stand_top_m / texel))
    reach = stadium.stand_top_m / math.tan(math.radians(stadium.stand_slope_deg))
    u_min = -(max(stadium.stand_half_x_m, stadium.stand_half_y_m) + reach)
    cols = int(math.ceil(-2 * u_min / texel))
    seat_w, row_h = 0.5, 0.42  # metres: seat width, rise per row
    palette = np.array([[40, 40, 200], [200, 200, 200], [30, 30, 30], [200, 120, 30], [60, 160, 220], [170, 60, 60],
                        [90, 90, 90], [30, 200, 240], [120, 40, 120], [210, 210, 240]], dtype=np.float32)
    cell_w, cell_h = max(2, int(round(seat_w / texel))), max(2, int(round(row_h / texel)))
    seats, seat_rows = int(math.ceil(cols / cell_w)), int(math.ceil(rows / cell_h))
    # One person per seat cell: torso colour, head on top; empty seats show the seat colour.
    person = np.zeros((cell_h, cell_w), dtype=np.float32)
    person[cell_h // 3:, 1:cell_w - 1] = 1.0
    head = np.zeros((cell_h, cell_w), dtype=np.float32)
    head[max(0, cell_h // 3 - max(1, cell_h // 4)):cell_h // 3, cell_w // 2 - max(1, cell_w // 6):cell_w // 2 + max(1, cell_w // 6)] = 1.0
    atlas = np.zeros((4 * rows, cols, 3), dtype=np.uint8)
    for side in range(4):
        colours = palette[rng.integers(len(palette), size=(seat_rows, seats))]
        colours *= rng.uniform(0.3, 0.85, size=(seat_rows, seats, 1)).astype(np.float32)
        colours = 0.75 * colours + 0.25 * colours.mean(axis=2, keepdims=True)  # less saturated
        occupied = rng.random((seat_rows, seats)) < 0.88
        seat_colour = np.array([110, 50, 30], dtype=np.float32) if side % 2 == 0 else np.array([40, 40, 120], dtype=np.float32)
        big = cv2.resize(colours, (seats * cell_w, seat_rows * cell_h), interpolation=cv2.INTER_NEAREST)
        occ = cv2.resize(occupied.astype(np.float32), (seats * cell_w, seat_rows * cell_h), interpolation=cv2.INTER_NEAREST)
        tile_p = np.tile(person, (seat_rows, seats))[..., None]
        tile_h = np.tile(head, (seat_rows, seats))[..., None]
        crowd = seat_colour * 0.5 * (1 - tile_p) + big * tile_p
        crowd = crowd * (1 - tile_h) + np.array([60, 90, 140], dtype=np.float32) * tile_h
        crowd = np.where(occ[..., None] > 0.5, crowd, seat_colour)
        crowd = crowd[:rows, :cols]
        crowd = crowd[::-1]  # row 0 = top of the stands
        crowd = np.ascontiguousarray(crowd)
        # Aisles (stairs) and a tier wall with an LED ribbon.
        for u in np.arange(u_min + rng.uniform(5, 15), -u_min, rng.uniform(14.0, 22.0)):
            c = int((u - u_min) / texel)
            crowd[:, c:c + max(1, int(1.2 / texel))] = (150, 150, 150)
        ribbon = int(rows * rng.uniform(0.35, 0.5))
        crowd[ribbon:ribbon + max(2, int(0.9 / texel))] = (30, 30, 30)
        crowd[ribbon + 1:ribbon + max(2, int(0.8 / texel))] = rng.integers(40, 255, size=3)
        crowd[rows - max(2, int(1.1 / texel)):] = (95, 100, 105)  # front wall at the foot
        shade = np.linspace(0.55, 1.0, rows, dtype=np.float32)[:, None, None]  # roof shadow at the top
        atlas[side * rows:(side + 1) * rows] = np.clip(crowd * shade, 0, 255).astype(np.uint8)
    atlas = cv2.GaussianBlur(atlas, (3, 3), 0.8)
    return atlas, rows, u_min


def make_textures(texel_m: float = 0.025, seed: int = 0, stadium: Stadium = DEFAULT_STADIUM, markings: bool = True,
                  stripes: bool = True) -> TextureSet:
    """All textures of the stadium (not cached: :func:`build_textures` is the cached form).

    Args:
        texel_m: ground texel size in metres (0.025 for HD, 0.05 for small images).
        seed: random seed of the textures.
        stadium: stadium geometry.
        markings: paint the markings into the ground texture (False: plain grass, for a renderer that
            paints them itself; the class-id texture is made all the same).
        stripes: mow stripes into the grass (False: no stripes).
    """
    pitch = PitchTemplate()
    rng = np.random.default_rng([int(seed), 7331])
    levels, class_ids, x_min, y_min = _ground(pitch, stadium, texel_m, rng, markings, stripes)
    board_texel = 0.02 if texel_m <= 0.03 else 0.04
    boards, board_rows, board_u_min = _boards(stadium, board_texel, rng)
    stand_texel = 0.06 if texel_m <= 0.03 else 0.1
    stands, stand_rows, stand_u_min = _stands(stadium, stand_texel, rng)
    return TextureSet(
        texel_m=texel_m, x_min_m=x_min, y_min_m=y_min, ground_levels=levels, class_ids=class_ids,
        boards=boards, board_texel_m=board_texel, board_rows=board_rows, board_u_min_m=board_u_min,
        stands=stands, stand_texel_m=stand_texel, stand_rows=stand_rows, stand_u_min_m=stand_u_min,
    )


@lru_cache(maxsize=2)
def build_textures(texel_m: float = 0.025, seed: int = 0, stadium: Stadium = DEFAULT_STADIUM) -> TextureSet:
    """All textures of the stadium, markings and stripes included (cached: the same arguments return the same object).

    Args:
        texel_m: ground texel size in metres (0.025 for HD, 0.05 for small images).
        seed: random seed of the textures.
        stadium: stadium geometry.
    """
    return make_textures(texel_m, seed, stadium)
