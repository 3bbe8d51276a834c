"""Ray casting of the background: every pixel's viewing ray through the camera model, where it
meets the ground, the advertising boards, the stands or the roof, and the colour it samples there.

1. the pixel's viewing ray: distorted normalised coordinates ``(u - cx) / f``, undone
   with the camera's k1 (the radial undistortion factor, a function of r_d^2 only, is
   solved by Newton's method on a 1-D table and looked up per pixel), rotated to the
   world by ``R_cw^T``;
2. the ray hits the ground plane z = 0, an advertising board (vertical walls around
   the pitch), the stands (four raked planes) or the roof, whichever comes first;
   ground pixels sample a precomputed top-down texture (grass, stripes, markings)
   with ``cv2.remap`` from the pyramid level matching their footprint (chosen per band
   of rows); the others sample the board and stand atlases (the crowd's texture
   coordinates at half resolution: it is clutter; which pixel is what stays exact).

Images are (H, W, 3) BGR uint8, labels (H, W) uint8 (drawing.SURFACE_*), rays and maps (H, W) float32.
"""

from __future__ import annotations

import math

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.distortion import undistort_normalized
from broadtrack_graph.synth.drawing import (
    SURFACE_BOARD,
    SURFACE_GROUND,
    SURFACE_ROOF,
    SURFACE_STAND,
    project_unfolded,
)
from broadtrack_graph.synth.scene import Stadium
from broadtrack_graph.synth.texture import TextureSet


def undistortion_scale(camera: Camera, rd2: np.ndarray) -> np.ndarray:
    """Per-pixel factor r / r_d (float32) from a 1-D Newton-solved table of r_d^2."""
    if camera.k1 == 0.0:
        return None
    r2_max = float(rd2.max()) * 1.0001 + 1e-12
    samples = 2048
    table_r2 = np.linspace(0.0, r2_max, samples)
    r_d = np.sqrt(table_r2)
    xy = undistort_normalized(np.column_stack([r_d, np.zeros_like(r_d)]), camera.k1)
    scale = np.where(r_d > 0, xy[:, 0] / np.where(r_d > 0, r_d, 1.0), 1.0).astype(np.float32)
    lut = scale.reshape(1, -1)
    map_x = rd2 * np.float32((samples - 1) / r2_max)
    map_y = np.zeros_like(map_x)
    return cv2.remap(lut, map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)


def pixel_rays(camera: Camera, u_px: np.ndarray, v_px: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """World directions (not unit) of every pixel's ray: three (H, W) float32 arrays.

    Args:
        camera: the camera at the image size (k1-only distortion).
        u_px: (W,) float32 pixel columns; v_px: (H,) float32 pixel rows.
    """
    if not camera.extra_distortion.is_zero:
        raise ValueError("the renderer supports k1 only; the camera has other distortion terms")
    cx, cy = camera.principal_point
    f = np.float32(camera.focal_px)
    xd = (u_px - np.float32(cx)) / f
    yd = (v_px - np.float32(cy)) / f
    xn = np.empty((len(v_px), len(u_px)), np.float32)
    yn = np.empty_like(xn)
    xn[:] = xd[None, :]
    yn[:] = yd[:, None]
    if camera.k1 != 0.0:
        rd2 = cv2.add(cv2.multiply(xn, xn), cv2.multiply(yn, yn))
        scale = undistortion_scale(camera, rd2)
        xn = cv2.multiply(xn, scale)
        yn = cv2.multiply(yn, scale)
    R = camera.R_cw.astype(np.float64)
    # ray_w = R^T [xn, yn, 1] = xn * R[0] + yn * R[1] + R[2]
    dx = cv2.addWeighted(xn, R[0, 0], yn, R[1, 0], R[2, 0])
    dy = cv2.addWeighted(xn, R[0, 1], yn, R[1, 1], R[2, 1])
    dz = cv2.addWeighted(xn, R[0, 2], yn, R[1, 2], R[2, 2])
    return dx, dy, dz


def ground_maps(camera: Camera, dx, dy, dz, stadium: Stadium, textures: TextureSet):
    """Ground hit (texel coordinates at level 0) and a mask of rays that surely hit the inner ground.

    Returns:
        X, Y: (H, W) float32 ground hit, metres; inv: (H, W) ray parameter to the ground;
        inner: (H, W) uint8 255 where the ray surely meets the ground inside the boards;
        map_x, map_y: (H, W) float32 texel coordinates of the hit at level 0.
    """
    C = camera.position_m
    tex = textures
    dz_safe = np.maximum(dz, np.float32(1e-6))
    inv = cv2.divide(np.float32(-C[2]), dz_safe)  # ray parameter to the ground (dz > 0 looks down)
    X = cv2.multiply(dx, inv)
    X += np.float32(C[0])
    Y = cv2.multiply(dy, inv)
    Y += np.float32(C[1])
    # Rays that surely meet the ground well inside the boards (uint8 255 / 0). Upward rays get a
    # huge ground hit from the clamped dz, so they fall outside the range by themselves.
    margin = 2.0
    hx, hy = stadium.board_half_x_m - margin, stadium.board_half_y_m - margin
    inner = cv2.bitwise_and(cv2.inRange(X, -hx, hx), cv2.inRange(Y, -hy, hy))
    scale = 1.0 / tex.texel_m
    map_x = cv2.transform(X, np.array([[scale, -tex.x_min_m * scale - 0.5]]))
    map_y = cv2.transform(Y, np.array([[scale, -tex.y_min_m * scale - 0.5]]))
    return X, Y, inv, inner, map_x, map_y


def sample_ground(camera: Camera, map_x, map_y, inv, dz, textures: TextureSet) -> np.ndarray:
    """Ground colours with the pyramid level chosen per band of rows from the pixel footprint."""
    tex = textures
    H, W = dz.shape
    out = np.empty((H, W, 3), np.uint8)
    # Footprint (metres per pixel, geometric mean of the two axes) on a coarse grid.
    step = 8
    inv_c = inv[::step, ::step]
    dz_c = np.maximum(dz[::step, ::step], 1e-6)
    footprint = inv_c / camera.focal_px / np.sqrt(dz_c)  # |d| ~ 1 folded in
    valid = dz[::step, ::step] > 1e-4
    level_c = np.log2(np.maximum(footprint / tex.texel_m, 1e-6)) - 1.0
    levels = len(tex.ground_levels)
    band = max(step, (H // 24) // step * step)
    for row0 in range(0, H, band):
        row1 = min(H, row0 + band)
        rows_c = slice(row0 // step, max(row0 // step + 1, (row1 + step - 1) // step))
        lv = level_c[rows_c][valid[rows_c]]
        level = int(np.clip(np.floor(np.percentile(lv, 30)) if lv.size else 0, 0, levels - 1))
        scale = np.float32(1.0 / (1 << level))
        mx = map_x[row0:row1]
        my = map_y[row0:row1]
        if level:
            mx = (mx + np.float32(0.5)) * scale - np.float32(0.5)
            my = (my + np.float32(0.5)) * scale - np.float32(0.5)
        cv2.remap(tex.ground_levels[level], mx, my, cv2.INTER_LINEAR, dst=out[row0:row1],
                  borderMode=cv2.BORDER_CONSTANT, borderValue=(0, 0, 0))
    return out


def board_rows(camera: Camera, stadium: Stadium, width_px: int, height_px: int) -> tuple[int, int] | None:
    """Image rows [r0, r1) that can show a board: the projected top and bottom board edges, with margin."""
    st = stadium
    bx, by = st.board_half_x_m, st.board_half_y_m
    edges = []
    for z in (0.0, -st.board_height_m):
        xs = np.arange(-bx, bx + 0.25, 0.25)
        ys = np.arange(-by, by + 0.25, 0.25)
        edges += [np.column_stack([xs, np.full_like(xs, s * by), np.full_like(xs, z)]) for s in (-1, 1)]
        edges += [np.column_stack([np.full_like(ys, s * bx), ys, np.full_like(ys, z)]) for s in (-1, 1)]
    uv, valid = project_unfolded(camera, np.vstack(edges))
    with np.errstate(invalid="ignore"):
        near = valid & (uv[:, 0] > -200) & (uv[:, 0] < width_px + 200)
    if not near.any():
        return None
    r0 = int(np.clip(np.floor(uv[near, 1].min()) - 4, 0, height_px))
    r1 = int(np.clip(np.ceil(uv[near, 1].max()) + 5, 0, height_px))
    return (r0, r1) if r1 > r0 else None


def surroundings(camera: Camera, image, labels, row0: int, row1: int, dx, dy, dz, X, Y, stadium: Stadium,
                 textures: TextureSet) -> None:
    """Boards, stands and roof in the rows [row0, row1) that hold rays leaving the inner pitch, in place.

    Dense float32 arithmetic over the band. Boards (only in the rows where the projected
    board edges are): a downward ray with ground hit G leaves the board rectangle at
    fraction s of C -> G (smallest s over the walls it crosses outwards), at height
    (1 - s) x camera height; below the board top it hits the board. With the camera
    outside the rectangle, rays entering it low hit the back of the near boards. Stands:
    the air above the four raked stands is convex and holds the camera, so a ray leaves
    it through the plane it approaches fastest (rate -g1 / g0), at t = 1 / rate; rays
    whose ground hit is inside the stand foot meet the ground first. The stand texture
    coordinates are computed at half resolution and interpolated (the crowd is clutter;
    which pixels are stands is decided at full resolution).
    """
    st = stadium
    tex = textures
    C = camera.position_m
    cx, cy = np.float32(C[0]), np.float32(C[1])
    band = slice(row0, row1)
    gx, gy = X[band], Y[band]
    img, lab = image[band], labels[band]
    one = np.float32(1.0)
    # Upward rays have a huge ground hit (clamped dz), so the ranges exclude them.
    in_foot = cv2.bitwise_and(cv2.inRange(gx, -st.stand_half_x_m, st.stand_half_x_m),
                              cv2.inRange(gy, -st.stand_half_y_m, st.stand_half_y_m)) > 0
    lab[in_foot] = SURFACE_GROUND
    board = np.zeros(gx.shape, bool)
    rows = board_rows(camera, stadium, image.shape[1], image.shape[0])
    if rows is not None and max(rows[0], row0) < min(rows[1], row1):
        sub = slice(max(rows[0], row0) - row0, min(rows[1], row1) - row0)
        boards(camera, img[sub], lab[sub], board[sub], gx[sub], gy[sub], dz[band][sub], in_foot[sub], stadium, textures)
    rest = ~in_foot & ~board
    rest_rows = np.flatnonzero(rest.any(axis=1))
    if rest_rows.size == 0:
        return
    sub = slice(rest_rows[0], rest_rows[-1] + 1)
    rest = rest[sub]
    h, w = rest.shape
    # Stand planes at half resolution.
    sdx, sdy, sdz = (a[band][sub][::2, ::2] for a in (dx, dy, dz))
    k = math.tan(math.radians(st.stand_slope_deg))
    g0s = (-C[2] + k * C[1] + k * st.stand_half_y_m, -C[2] - k * C[1] + k * st.stand_half_y_m,
           -C[2] + k * C[0] + k * st.stand_half_x_m, -C[2] - k * C[0] + k * st.stand_half_x_m)
    best_rate = cv2.addWeighted(sdz, 1.0 / g0s[0], sdy, -k / g0s[0], 0.0)
    side = np.zeros(best_rate.shape, np.uint8)
    for side_index, (other, sign) in enumerate(((sdy, 1.0), (sdx, -1.0), (sdx, 1.0)), start=1):
        rate = cv2.addWeighted(sdz, 1.0 / g0s[side_index], other, sign * k / g0s[side_index], 0.0)
        side[rate > best_rate] = side_index
        np.maximum(best_rate, rate, out=best_rate)
    t = one / np.maximum(best_rate, np.float32(1e-9))
    height = -(np.float32(C[2]) + t * sdz)
    is_stand = ((best_rate > 1e-9) & (height <= st.stand_top_m)).astype(np.uint8)
    u = np.where(side >= 2, cy + t * sdy, cx + t * sdx)
    map_x = (u - np.float32(tex.stand_u_min_m)) * np.float32(1.0 / tex.stand_texel_m) - np.float32(0.5)
    from_top = (np.float32(st.stand_top_m) - height) * np.float32(1.0 / tex.stand_texel_m) - np.float32(0.5)
    map_y = side.astype(np.float32) * np.float32(tex.stand_rows) + np.clip(from_top, 0, tex.stand_rows - 1)
    map_x = cv2.resize(map_x, (w, h), interpolation=cv2.INTER_LINEAR)
    map_y = cv2.resize(map_y, (w, h), interpolation=cv2.INTER_LINEAR)
    stand = rest & (cv2.resize(is_stand, (w, h), interpolation=cv2.INTER_NEAREST) > 0)
    roof = rest & ~stand
    sub_img, sub_lab = img[sub], lab[sub]
    if stand.any():
        colours = cv2.remap(tex.stands, map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
        cv2.copyTo(colours, stand.astype(np.uint8), sub_img)
        sub_lab[stand] = SURFACE_STAND
    if roof.any():
        sub_img[roof] = roof_colour(dz[band][sub][roof])
        sub_lab[roof] = SURFACE_ROOF


def boards(camera: Camera, img, lab, board, gx, gy, gdz, in_foot, stadium: Stadium, textures: TextureSet) -> None:
    """Board pixels of a band (see surroundings), in place: colours, labels and the board mask."""
    st = stadium
    tex = textures
    C = camera.position_m
    cx, cy = np.float32(C[0]), np.float32(C[1])
    one, inf = np.float32(1.0), np.float32(np.inf)
    looks_down = gdz > 1e-6
    in_boards = in_foot & (np.abs(gx) <= st.board_half_x_m) & (np.abs(gy) <= st.board_half_y_m)
    height_cam = np.float32(-C[2])
    hb = np.float32(st.board_height_m)
    # (coordinate of G along the wall normal, camera's, wall position, the other coordinate, its
    # camera value, the wall's half extent along it, wall index)
    walls = ((gy, cy, -st.board_half_y_m, gx, cx, st.board_half_x_m, 0),
             (gy, cy, st.board_half_y_m, gx, cx, st.board_half_x_m, 1),
             (gx, cx, -st.board_half_x_m, gy, cy, st.board_half_y_m, 2),
             (gx, cx, st.board_half_x_m, gy, cy, st.board_half_y_m, 3))
    s_exit = np.full(gx.shape, inf, np.float32)
    wall = np.zeros(gx.shape, np.int8)
    s_enter = np.full(gx.shape, -inf, np.float32)
    camera_outside = False
    with np.errstate(divide="ignore", invalid="ignore"):
        for coord, cam, limit, other, other_cam, extent, index in walls:
            limit = np.float32(limit)
            s_wall = (limit - cam) / (coord - cam)
            # The crossing must be on the wall itself, not on its plane beyond a corner.
            on_wall = np.abs(other_cam + s_wall * (other - other_cam)) <= extent
            if (cam <= limit) if limit < 0 else (cam >= limit):  # camera beyond this wall: rays enter
                camera_outside = True
                enters = on_wall & (s_wall > s_enter)
                s_enter[enters] = s_wall[enters]
                continue
            beyond = on_wall & ((coord < limit) if limit < 0 else (coord > limit))
            better = beyond & (s_wall < s_exit)
            s_exit[better] = s_wall[better]
            wall[better] = index
    front = looks_down & ~in_boards & (s_exit <= one) & (height_cam * (one - s_exit) <= hb)
    board[:] = front
    if camera_outside:
        board |= in_boards & (s_enter > 0) & (height_cam * (one - s_enter) <= hb)
    if front.any():
        rows = np.flatnonzero(front.any(axis=1))
        sub = slice(rows[0], rows[-1] + 1)
        s_b = np.where(front[sub], s_exit[sub], np.float32(0.0))
        # u runs left to right as seen from the pitch: +x on the far wall, -x on the near one,
        # -y on the left wall, +y on the right one.
        along = np.where(wall[sub] >= 2, cy + s_b * (gy[sub] - cy), cx + s_b * (gx[sub] - cx))
        u = np.where((wall[sub] == 1) | (wall[sub] == 2), -along, along)
        map_x = (u - np.float32(tex.board_u_min_m)) * np.float32(1.0 / tex.board_texel_m) - np.float32(0.5)
        top_down = (hb - height_cam * (one - s_b)) * np.float32(1.0 / tex.board_texel_m) - np.float32(0.5)
        map_y = wall[sub].astype(np.float32) * np.float32(tex.board_rows) + np.clip(top_down, 0, tex.board_rows - 1)
        colours = cv2.remap(tex.boards, map_x, map_y, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
        cv2.copyTo(colours, front[sub].astype(np.uint8), img[sub])
    back_only = board & ~front
    if back_only.any():
        img[back_only] = (50, 52, 55)  # back of the near boards
    lab[board] = SURFACE_BOARD


def roof_colour(dz: np.ndarray) -> np.ndarray:
    """Dark roof underside, slightly lighter towards the horizon (N, 3) uint8."""
    shade = np.clip(60.0 + 200.0 * np.maximum(dz + 0.05, 0.0), 40.0, 90.0)
    return np.column_stack([shade * 1.05, shade * 1.0, shade * 0.95]).astype(np.uint8)
