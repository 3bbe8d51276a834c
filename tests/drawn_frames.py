"""Test frames drawn from a camera: striped-free green grass, white markings, dark stands, player boxes."""

from __future__ import annotations

import cv2
import numpy as np

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves

PITCH = PitchTemplate()
FINE = TemplateCurves(PITCH, line_step_m=0.1, circle_step_m=0.05)


def draw_frame(camera, seed=0, players=12, hidden=(), line_grey=235):
    """(image (H, W, 3) uint8 BGR at the camera's size, player boxes (P, 4) pixels).

    Grass with the ground markings 2 px wide (drawn 4x supersampled), grey stands around the
    pitch, Gaussian noise (sigma 3) and red player rectangles. ``hidden``: class names not drawn
    (markings the frame does not show); ``line_grey``: the markings' grey level.
    """
    W, H = camera.width_px, camera.height_px
    rng = np.random.default_rng(seed)
    scale = 4
    big = np.zeros((H * scale, W * scale, 3), np.uint8)
    big[:] = (40, 40, 40)
    hi = camera.rescaled(W * scale, H * scale)
    outline, _ = hi.project(np.vstack([PITCH.outline_w * 1.15]))
    cv2.fillPoly(big, [np.round(outline).astype(np.int32)], (40, 140, 50))
    for name, pts in FINE.samples_w.items():
        if not PITCH.is_on_ground(name) or name in hidden:
            continue
        uv, front = hi.project(pts)
        ok = front & np.all(np.abs(uv) < 1e5, axis=1)
        if ok.sum() > 1:
            cv2.polylines(big, [np.round(uv[ok] * 16).astype(np.int32)], False, (line_grey,) * 3, 2 * scale,
                          cv2.LINE_AA, 4)
    image = cv2.resize(big, (W, H), interpolation=cv2.INTER_AREA).astype(np.int16)
    image += rng.normal(0, 3, image.shape).astype(np.int16)
    image = np.clip(image, 0, 255).astype(np.uint8)
    boxes = []
    for _ in range(players):
        x, y = int(rng.uniform(20, W - 20)), int(rng.uniform(H * 0.45, H - 30))
        cv2.rectangle(image, (x, y), (x + 8, y + 22), (30, 30, 200), -1)
        boxes.append((x, y, x + 8, y + 22))
    return image, np.array(boxes, float).reshape(-1, 4)
