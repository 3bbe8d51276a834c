"""Goals and players drawn over the background: goal posts, crossbar and net, player figures
with their shadows, in far-to-near order, projected with the same camera (``Camera.project``,
distortion included); they stand on the pitch, in front of the ground they cover.
"""

from __future__ import annotations

import math

import cv2
import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.synth.drawing import SURFACE_GOAL, SURFACE_PLAYER, any_near_image, fixed_point, project_unfolded
from broadtrack_graph.synth.scene import GoalPart, PlayerTrack

TEAM_COLOURS_BGR = {
    0: ((245, 245, 245), (40, 40, 40), (245, 245, 245)),  # shirt, shorts, socks
    1: ((40, 40, 200), (240, 240, 240), (40, 40, 200)),
    2: ((30, 30, 30), (30, 30, 30), (30, 30, 30)),  # referee
    3: ((20, 200, 230), (20, 20, 20), (20, 200, 230)),  # goalkeeper
}
SKIN_BGR = (120, 150, 200)


def draw_objects(camera: Camera, image, labels, goal_parts: list[GoalPart], players: PlayerTrack | None,
                 frame_index: int) -> np.ndarray:
    """Goals and players, far to near, in place; returns the player boxes (M, 5) [player, x0, y0, x1, y1] pixels.

    Args:
        goal_parts: the goal parts to draw (empty: no goals).
        players: the clip's player track (None: no players); positions of frame_index are drawn.
    """
    items = []  # (depth, kind, payload)
    C = camera.position_m
    for part in goal_parts:
        centre = part.points_w.mean(axis=0)
        items.append((float(np.linalg.norm(centre - C)), "goal", part))
    if players is not None and players.positions_w.shape[1]:
        feet = players.positions_w[min(frame_index, len(players.positions_w) - 1)]
        for p in range(len(feet)):
            items.append((float(np.linalg.norm(feet[p] - C)), "player", p))
    items.sort(key=lambda item: -item[0])
    boxes = []
    # Player shadows first: they lie on the ground under everything else.
    if players is not None and players.positions_w.shape[1]:
        draw_shadows(camera, image, players, frame_index)
    for depth, kind, payload in items:
        if kind == "goal":
            draw_goal_part(camera, image, labels, payload, depth)
        else:
            box = draw_player(camera, image, labels, players, frame_index, payload)
            if box is not None:
                boxes.append([payload, *box])
    return np.asarray(boxes, dtype=float).reshape(-1, 5)


def draw_goal_part(camera: Camera, image, labels, part: GoalPart, depth: float):
    """One goal part (post or bar as a tube, or a net panel), in place; returns the tube width in pixels or None."""
    height_px, width_px = image.shape[:2]
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
        if not any_near_image(uv, width_px, height_px):
            return None
        poly = fixed_point(uv[-4:])
        x0, y0 = np.clip(np.floor(uv[-4:].min(axis=0)).astype(int) - 2, 0, [width_px, height_px])
        x1, y1 = np.clip(np.ceil(uv[-4:].max(axis=0)).astype(int) + 2, 0, [width_px, height_px])
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
    if not valid.all() or not any_near_image(uv, width_px, height_px):
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


def player_polygons(camera: Camera, foot_w: np.ndarray, height_m: float, phase: float):
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


def draw_player(camera: Camera, image, labels, players: PlayerTrack, frame_index: int, p: int):
    """Player p as an upright figure, in place; returns its box [x0, y0, x1, y1] pixels, or None when out of view."""
    height_px, width_px = image.shape[:2]
    i = min(frame_index, len(players.positions_w) - 1)
    foot = players.positions_w[i, p]
    polys, head_centre = player_polygons(camera, foot, float(players.heights_m[p]), float(players.phases[i, p]))
    pts = np.vstack([q for _, q in polys] + [head_centre[None], (head_centre + np.array([0, 0, -0.12]))[None]])
    uv, valid = project_unfolded(camera, pts)
    if not valid.all():
        return None
    x_min, y_min = uv.min(axis=0)
    x_max, y_max = uv.max(axis=0)
    if x_max < 0 or y_max < 0 or x_min >= width_px or y_min >= height_px:
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
    box = [max(0.0, x_min), max(0.0, y_min - radius), min(width_px - 1.0, x_max), min(height_px - 1.0, y_max)]
    return box


def draw_shadows(camera: Camera, image, players: PlayerTrack, frame_index: int) -> None:
    """Soft dark ellipses on the ground under the players, drawn in each shadow's own box."""
    height_px, width_px = image.shape[:2]
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
        if not valid.all() or not any_near_image(uv, width_px, height_px, margin=0.0):
            continue
        x0, y0 = np.clip(np.floor(uv.min(axis=0)).astype(int) - 3, 0, [width_px, height_px])
        x1, y1 = np.clip(np.ceil(uv.max(axis=0)).astype(int) + 4, 0, [width_px, height_px])
        if x1 - x0 < 2 or y1 - y0 < 2:
            continue
        shadow = np.zeros((y1 - y0, x1 - x0), np.uint8)
        cv2.fillPoly(shadow, [fixed_point(uv - [x0, y0])], 255, cv2.LINE_AA, 4)
        shadow = cv2.GaussianBlur(shadow, (5, 5), 1.0)
        gain = 255 - (shadow.astype(np.uint16) * 100 // 255).astype(np.uint8)
        roi = image[y0:y1, x0:x1]
        cv2.multiply(roi, cv2.merge([gain, gain, gain]), dst=roi, scale=1.0 / 255)
