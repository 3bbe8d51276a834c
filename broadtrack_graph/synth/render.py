"""Ray-casting renderer of broadcast frames through the tracker's exact camera model.

Per frame and per pixel (float32, vectorised):

1. the pixel's viewing ray: distorted normalised coordinates ``(u - cx) / f``, undone
   with the camera's k1 (the radial undistortion factor, a function of r_d^2 only, is
   solved by Newton's method on a 1-D table and looked up per pixel), rotated to the
   world by ``R_cw^T``;
2. the ray hits the ground plane z = 0, an advertising board (vertical walls around
   the pitch), the stands (four raked planes) or the roof, whichever comes first;
   ground pixels sample a precomputed top-down texture (grass, stripes, markings)
   with ``cv2.remap`` from the pyramid level matching their footprint (chosen per band
   of rows); the others sample the board and stand atlases (the crowd's texture
   coordinates at half resolution: it is clutter; which pixel is what stays exact);
3. goals (posts, crossbar, net) and players (upright figures with shadows) are drawn
   on top in far-to-near order by projecting their 3D geometry with the same camera
   (``Camera.project``, distortion included); they stand on the pitch, in front of
   the ground they cover;
4. a moving shadow band and exposure drift, motion blur along the image motion
   between the previous and the current camera, lens softness, vignetting and
   sensor noise; optionally a JPEG round trip.

Besides the BGR image, the renderer returns a per-pixel surface label (what the ray
hit) and, on request, the class id of the marking under each ground pixel: the
ground truth uses them to decide what an annotator can see. No I/O here.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera, undistort_normalized
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.synth.scene import DEFAULT_STADIUM, GoalPart, PlayerTrack, Stadium, goal_parts
from broadtrack_graph.synth.texture import TextureSet, build_textures

# Surface labels of the label image.
SURFACE_NONE = 0
SURFACE_GROUND = 1
SURFACE_BOARD = 2
SURFACE_STAND = 3
SURFACE_ROOF = 4
SURFACE_GOAL = 5
SURFACE_PLAYER = 6

TEAM_COLOURS_BGR = {
    0: ((245, 245, 245), (40, 40, 40), (245, 245, 245)),  # shirt, shorts, socks
    1: ((40, 40, 200), (240, 240, 240), (40, 40, 200)),
    2: ((30, 30, 30), (30, 30, 30), (30, 30, 30)),  # referee
    3: ((20, 200, 230), (20, 20, 20), (20, 200, 230)),  # goalkeeper
}
SKIN_BGR = (120, 150, 200)


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
    """

    def __init__(self, width_px: int, height_px: int, seed: int = 0, settings: RenderSettings = RenderSettings(),
                 stadium: Stadium = DEFAULT_STADIUM) -> None:
        if width_px < 16 or height_px < 16:
            raise ValueError(f"image size must be at least 16x16, got {width_px}x{height_px}")
        self.width_px, self.height_px = int(width_px), int(height_px)
        self.settings = settings
        self.stadium = stadium
        self.pitch = PitchTemplate()
        texel = 0.025 if width_px >= 1280 else 0.05
        self.textures: TextureSet = build_textures(texel, int(seed) % 4, stadium)
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

    # ----------------------------------------------------------------- rays

    def _undistortion_scale(self, camera: Camera, rd2: np.ndarray) -> np.ndarray:
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

    def rays(self, camera: Camera) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """World directions (not unit) of every pixel's ray: three (H, W) float32 arrays."""
        if camera.width_px != self.width_px or camera.height_px != self.height_px:
            camera = camera.rescaled(self.width_px, self.height_px)
        if not camera.extra_distortion.is_zero:
            raise ValueError("the renderer supports k1 only; the camera has other distortion terms")
        cx, cy = camera.principal_point
        f = np.float32(camera.focal_px)
        xd = (self._u - np.float32(cx)) / f
        yd = (self._v - np.float32(cy)) / f
        xn = np.empty((self.height_px, self.width_px), np.float32)
        yn = np.empty_like(xn)
        xn[:] = xd[None, :]
        yn[:] = yd[:, None]
        if camera.k1 != 0.0:
            rd2 = cv2.add(cv2.multiply(xn, xn), cv2.multiply(yn, yn))
            scale = self._undistortion_scale(camera, rd2)
            xn = cv2.multiply(xn, scale)
            yn = cv2.multiply(yn, scale)
        R = camera.R_cw.astype(np.float64)
        # ray_w = R^T [xn, yn, 1] = xn * R[0] + yn * R[1] + R[2]
        dx = cv2.addWeighted(xn, R[0, 0], yn, R[1, 0], R[2, 0])
        dy = cv2.addWeighted(xn, R[0, 1], yn, R[1, 1], R[2, 1])
        dz = cv2.addWeighted(xn, R[0, 2], yn, R[1, 2], R[2, 2])
        return dx, dy, dz

    # ----------------------------------------------------------------- background

    def _ground_maps(self, camera: Camera, dx, dy, dz):
        """Ground hit (texel coordinates at level 0) and a mask of rays that surely hit the inner ground."""
        C = camera.position_m
        tex = self.textures
        dz_safe = np.maximum(dz, np.float32(1e-6))
        inv = cv2.divide(np.float32(-C[2]), dz_safe)  # ray parameter to the ground (dz > 0 looks down)
        X = cv2.multiply(dx, inv)
        X += np.float32(C[0])
        Y = cv2.multiply(dy, inv)
        Y += np.float32(C[1])
        # Rays that surely meet the ground well inside the boards (uint8 255 / 0). Upward rays get a
        # huge ground hit from the clamped dz, so they fall outside the range by themselves.
        margin = 2.0
        hx, hy = self.stadium.board_half_x_m - margin, self.stadium.board_half_y_m - margin
        inner = cv2.bitwise_and(cv2.inRange(X, -hx, hx), cv2.inRange(Y, -hy, hy))
        scale = 1.0 / tex.texel_m
        map_x = cv2.transform(X, np.array([[scale, -tex.x_min_m * scale - 0.5]]))
        map_y = cv2.transform(Y, np.array([[scale, -tex.y_min_m * scale - 0.5]]))
        return X, Y, inv, inner, map_x, map_y

    def _sample_ground(self, camera: Camera, map_x, map_y, inv, dz) -> np.ndarray:
        """Ground colours with the pyramid level chosen per band of rows from the pixel footprint."""
        tex = self.textures
        H, W = self.height_px, self.width_px
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

    def _board_rows(self, camera: Camera) -> tuple[int, int] | None:
        """Image rows [r0, r1) that can show a board: the projected top and bottom board edges, with margin."""
        st = self.stadium
        bx, by = st.board_half_x_m, st.board_half_y_m
        edges = []
        for z in (0.0, -st.board_height_m):
            xs = np.arange(-bx, bx + 0.25, 0.25)
            ys = np.arange(-by, by + 0.25, 0.25)
            edges += [np.column_stack([xs, np.full_like(xs, s * by), np.full_like(xs, z)]) for s in (-1, 1)]
            edges += [np.column_stack([np.full_like(ys, s * bx), ys, np.full_like(ys, z)]) for s in (-1, 1)]
        uv, valid = project_unfolded(camera, np.vstack(edges))
        with np.errstate(invalid="ignore"):
            near = valid & (uv[:, 0] > -200) & (uv[:, 0] < self.width_px + 200)
        if not near.any():
            return None
        r0 = int(np.clip(np.floor(uv[near, 1].min()) - 4, 0, self.height_px))
        r1 = int(np.clip(np.ceil(uv[near, 1].max()) + 5, 0, self.height_px))
        return (r0, r1) if r1 > r0 else None

    def _surroundings(self, camera: Camera, image, labels, row0: int, row1: int, dx, dy, dz, X, Y) -> None:
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
        st = self.stadium
        tex = self.textures
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
        rows = self._board_rows(camera)
        if rows is not None and max(rows[0], row0) < min(rows[1], row1):
            sub = slice(max(rows[0], row0) - row0, min(rows[1], row1) - row0)
            self._boards(camera, img[sub], lab[sub], board[sub], gx[sub], gy[sub], dz[band][sub], in_foot[sub])
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
            sub_img[roof] = _roof_colour(dz[band][sub][roof])
            sub_lab[roof] = SURFACE_ROOF

    def _boards(self, camera: Camera, img, lab, board, gx, gy, gdz, in_foot) -> None:
        """Board pixels of a band (see _surroundings), in place: colours, labels and the board mask."""
        st = self.stadium
        tex = self.textures
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

    # ----------------------------------------------------------------- objects

    def _draw_objects(self, camera: Camera, image, labels, players: PlayerTrack | None, frame_index: int,
                      ) -> np.ndarray:
        """Goals and players, far to near; returns the player boxes (M, 5)."""
        items = []  # (depth, kind, payload)
        C = camera.position_m
        if self.settings.goals:
            for part in self.goal_parts:
                centre = part.points_w.mean(axis=0)
                items.append((float(np.linalg.norm(centre - C)), "goal", part))
        if self.settings.players and players is not None and players.positions_w.shape[1]:
            feet = players.positions_w[min(frame_index, len(players.positions_w) - 1)]
            for p in range(len(feet)):
                items.append((float(np.linalg.norm(feet[p] - C)), "player", p))
        items.sort(key=lambda item: -item[0])
        boxes = []
        # Player shadows first: they lie on the ground under everything else.
        if self.settings.players and players is not None and players.positions_w.shape[1]:
            self._draw_shadows(camera, image, players, frame_index)
        for depth, kind, payload in items:
            if kind == "goal":
                self._draw_goal_part(camera, image, labels, payload, depth)
            else:
                box = self._draw_player(camera, image, labels, players, frame_index, payload)
                if box is not None:
                    boxes.append([payload, *box])
        return np.asarray(boxes, dtype=float).reshape(-1, 5)

    def _draw_goal_part(self, camera: Camera, image, labels, part: GoalPart, depth: float):
        f = camera.focal_px
        if part.kind == "net":
            corners = part.points_w
            n = 10
            a = np.linspace(0, 1, n)
            lines = []
            for t in a:  # mesh lines in both directions
                lines.append(np.stack([corners[0] + t * (corners[1] - corners[0]), corners[3] + t * (corners[2] - corners[3])]))
                lines.append(np.stack([corners[0] + t * (corners[3] - corners[0]), corners[1] + t * (corners[2] - corners[1])]))
            pts = np.vstack(lines + [corners])
            uv, valid = project_unfolded(camera, pts)
            if not valid.all():
                return None
            if not _any_near_image(uv, self.width_px, self.height_px):
                return None
            poly = fixed_point(uv[-4:])
            x0, y0 = np.clip(np.floor(uv[-4:].min(axis=0)).astype(int) - 2, 0, [self.width_px, self.height_px])
            x1, y1 = np.clip(np.ceil(uv[-4:].max(axis=0)).astype(int) + 2, 0, [self.width_px, self.height_px])
            if x1 <= x0 or y1 <= y0:
                return None
            roi = image[y0:y1, x0:x1]
            overlay = roi.copy()
            cv2.fillPoly(overlay, [poly - np.array([x0 * 16, y0 * 16])], (215, 215, 215), cv2.LINE_AA, 4)
            cv2.addWeighted(roi, 0.8, overlay, 0.2, 0, dst=roi)
            segs = fixed_point(uv[:-4]).reshape(-1, 2, 2)
            cv2.polylines(image, list(segs), False, (205, 205, 205), 1, cv2.LINE_AA, 4)
            return None
        pts = part.points_w[0] + np.linspace(0, 1, 12)[:, None] * (part.points_w[1] - part.points_w[0])
        uv, valid = project_unfolded(camera, pts)
        if not valid.all() or not _any_near_image(uv, self.width_px, self.height_px):
            return None
        width = 2.0 * part.radius_m * f / max(depth, 1e-3)
        thickness = max(1, int(round(width)))
        poly = fixed_point(uv).reshape(-1, 1, 2)
        colour = (238, 240, 240) if part.kind == "frame" else (190, 190, 190)
        cv2.polylines(image, [poly], False, colour, thickness, cv2.LINE_AA, 4)
        if width >= 3:  # a shaded side on thick tubes
            cv2.polylines(image, [poly + np.array([int(width * 4), 0])], False, (200, 204, 204), max(1, thickness // 3),
                          cv2.LINE_AA, 4)
        cv2.polylines(labels, [poly], False, SURFACE_GOAL, thickness, cv2.LINE_8, 4)
        return width

    def _player_polygons(self, camera: Camera, foot_w: np.ndarray, height_m: float, phase: float):
        """World polygons (list of (colour key, (K, 3))) of a figure facing the camera."""
        C = camera.position_m
        view = foot_w[:2] - C[:2]
        view /= max(np.linalg.norm(view), 1e-6)
        side = np.array([-view[1], view[0], 0.0])
        up = np.array([0.0, 0.0, -1.0])
        h = height_m
        swing = 0.16 * math.sin(phase)
        arm = 0.12 * math.sin(phase + math.pi)

        def quad(x0, x1, z0, z1, lean0=0.0, lean1=0.0):
            return np.array([foot_w + side * (x0 + lean0) + up * z0, foot_w + side * (x1 + lean0) + up * z0,
                             foot_w + side * (x1 + lean1) + up * z1, foot_w + side * (x0 + lean1) + up * z1])

        polys = [
            ("sock", quad(-0.17 + swing, -0.05 + swing, 0.0, 0.28 * h, 0.0, -swing * 0.5)),
            ("sock", quad(0.05 - swing, 0.17 - swing, 0.0, 0.28 * h, 0.0, swing * 0.5)),
            ("skin", quad(-0.16 + swing * 0.5, -0.04 + swing * 0.5, 0.27 * h, 0.47 * h, 0.0, -swing * 0.5)),
            ("skin", quad(0.04 - swing * 0.5, 0.16 - swing * 0.5, 0.27 * h, 0.47 * h, 0.0, swing * 0.5)),
            ("shorts", quad(-0.19, 0.19, 0.44 * h, 0.56 * h)),
            ("shirt", quad(-0.21, 0.21, 0.54 * h, 0.82 * h)),
            ("shirt", quad(-0.29, -0.2, 0.62 * h, 0.81 * h, arm, 0.0)),
            ("shirt", quad(0.2, 0.29, 0.62 * h, 0.81 * h, -arm, 0.0)),
            ("skin", quad(-0.06, 0.06, 0.81 * h, 0.86 * h)),
        ]
        head_centre = foot_w + up * (0.92 * h)
        return polys, head_centre

    def _draw_player(self, camera: Camera, image, labels, players: PlayerTrack, frame_index: int, p: int):
        i = min(frame_index, len(players.positions_w) - 1)
        foot = players.positions_w[i, p]
        polys, head_centre = self._player_polygons(camera, foot, float(players.heights_m[p]), float(players.phases[i, p]))
        pts = np.vstack([q for _, q in polys] + [head_centre[None], (head_centre + np.array([0, 0, -0.12]))[None]])
        uv, valid = project_unfolded(camera, pts)
        if not valid.all():
            return None
        x_min, y_min = uv.min(axis=0)
        x_max, y_max = uv.max(axis=0)
        if x_max < 0 or y_max < 0 or x_min >= self.width_px or y_min >= self.height_px:
            return None
        shirt, shorts, socks = TEAM_COLOURS_BGR[int(players.teams[p]) % len(TEAM_COLOURS_BGR)]
        colours = {"shirt": shirt, "shorts": shorts, "sock": socks, "skin": SKIN_BGR}
        offset = 0
        for key, quad in polys:
            q = fixed_point(uv[offset:offset + 4])
            offset += 4
            cv2.fillConvexPoly(image, q, colours[key], cv2.LINE_AA, 4)
            cv2.fillConvexPoly(labels, q, SURFACE_PLAYER, cv2.LINE_8, 4)
        head = uv[offset]
        radius = max(0.5, float(np.linalg.norm(uv[offset + 1] - uv[offset])))
        centre = tuple(int(v) for v in fixed_point(head[None])[0])
        cv2.circle(image, centre, int(round(radius * 16)), (40, 50, 70), -1, cv2.LINE_AA, 4)
        cv2.circle(labels, centre, int(round(radius * 16)), SURFACE_PLAYER, -1, cv2.LINE_8, 4)
        box = [max(0.0, x_min), max(0.0, y_min - radius), min(self.width_px - 1.0, x_max), min(self.height_px - 1.0, y_max)]
        return box

    def _draw_shadows(self, camera: Camera, image, players: PlayerTrack, frame_index: int) -> None:
        """Soft dark ellipses on the ground under the players, drawn in each shadow's own box."""
        i = min(frame_index, len(players.positions_w) - 1)
        feet = players.positions_w[i]
        sun = np.array([0.55, -0.35])  # shadow direction on the ground (unit-ish), metres per metre of height
        angles = np.linspace(0, 2 * math.pi, 14, endpoint=False)
        for p in range(len(feet)):
            h = float(players.heights_m[p])
            axis = sun * h
            centre = feet[p, :2] + 0.5 * axis
            length = np.linalg.norm(axis) * 0.5 + 0.15
            direction = axis / max(np.linalg.norm(axis), 1e-6)
            normal = np.array([-direction[1], direction[0]])
            ring = centre + np.cos(angles)[:, None] * direction * length + np.sin(angles)[:, None] * normal * 0.22
            uv, valid = project_unfolded(camera, np.column_stack([ring, np.zeros(len(ring))]))
            if not valid.all() or not _any_near_image(uv, self.width_px, self.height_px, margin=0.0):
                continue
            x0, y0 = np.clip(np.floor(uv.min(axis=0)).astype(int) - 3, 0, [self.width_px, self.height_px])
            x1, y1 = np.clip(np.ceil(uv.max(axis=0)).astype(int) + 4, 0, [self.width_px, self.height_px])
            if x1 - x0 < 2 or y1 - y0 < 2:
                continue
            shadow = np.zeros((y1 - y0, x1 - x0), np.uint8)
            cv2.fillPoly(shadow, [fixed_point(uv - [x0, y0])], 255, cv2.LINE_AA, 4)
            shadow = cv2.GaussianBlur(shadow, (5, 5), 1.0)
            gain = 255 - (shadow.astype(np.uint16) * 100 // 255).astype(np.uint8)
            roi = image[y0:y1, x0:x1]
            cv2.multiply(roi, cv2.merge([gain, gain, gain]), dst=roi, scale=1.0 / 255)

    # ----------------------------------------------------------------- whole frame

    def render(self, camera: Camera, players: PlayerTrack | None = None, frame_index: int = 0,
               previous_camera: Camera | None = None, want_class_ids: bool = False, time_s: float | None = None
               ) -> RenderedFrame:
        """Render one frame.

        Args:
            camera: the camera (rescaled to the renderer's size if needed; k1-only distortion).
            players: player track of the clip (positions of frame_index are drawn), or None.
            frame_index: index into the player track and the noise / lighting sequences.
            previous_camera: camera of the previous frame, for motion blur (None: no blur).
            want_class_ids: also return the marking class id under every ground pixel.
            time_s: clip time for the lighting (default frame_index / 25).

        Returns:
            RenderedFrame.
        """
        if camera.width_px != self.width_px or camera.height_px != self.height_px:
            camera = camera.rescaled(self.width_px, self.height_px)
        settings = self.settings
        H, W = self.height_px, self.width_px
        time_s = frame_index / 25.0 if time_s is None else time_s
        dx, dy, dz = self.rays(camera)
        X, Y, inv, inner, map_x, map_y = self._ground_maps(camera, dx, dy, dz)
        image = self._sample_ground(camera, map_x, map_y, inv, dz)
        labels = np.minimum(inner, np.uint8(SURFACE_GROUND))  # SURFACE_GROUND where inner, SURFACE_NONE elsewhere
        outer_rows = np.flatnonzero(inner.min(axis=1) == 0)
        if outer_rows.size:
            self._surroundings(camera, image, labels, int(outer_rows[0]), int(outer_rows[-1]) + 1, dx, dy, dz, X, Y)
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
        boxes = self._draw_objects(camera, image, labels, players, frame_index)
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


def project_unfolded(camera: Camera, points_w: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Project points; valid (N,) is False behind the camera and where a k1 < 0 model folds.

    With k1 < 0, ``r (1 + k1 r^2)`` turns back beyond ``r^2 = 1 / (3 |k1|)``; points beyond are
    not seen by any pixel (the rays are undistorted on the first branch), so they are not drawn.
    """
    uv, front = camera.project(points_w)
    if camera.k1 >= 0:
        return uv, front
    points_c = camera.world_to_camera(points_w)
    with np.errstate(invalid="ignore", divide="ignore"):
        r2 = (points_c[:, 0] ** 2 + points_c[:, 1] ** 2) / points_c[:, 2] ** 2
    return uv, front & (r2 < 1.0 / (3.0 * -camera.k1))


def fixed_point(uv_px: np.ndarray) -> np.ndarray:
    """(N, 2) pixels -> int32 coordinates with 4 fractional bits for OpenCV drawing (shift=4), clipped far outside."""
    return np.round(np.clip(uv_px, -1e5, 1e5) * 16).astype(np.int32)


def _roof_colour(dz: np.ndarray) -> np.ndarray:
    """Dark roof underside, slightly lighter towards the horizon (N, 3) uint8."""
    shade = np.clip(60.0 + 200.0 * np.maximum(dz + 0.05, 0.0), 40.0, 90.0)
    return np.column_stack([shade * 1.05, shade * 1.0, shade * 0.95]).astype(np.uint8)


def _any_near_image(uv: np.ndarray, width: int, height: int, margin: float = 50.0) -> bool:
    finite = np.isfinite(uv).all(axis=1)
    if not finite.any():
        return False
    u, v = uv[finite, 0], uv[finite, 1]
    return bool(u.max() >= -margin and u.min() < width + margin and v.max() >= -margin and v.min() < height + margin)
