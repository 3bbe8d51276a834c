"""The static graphics mask (broadtrack_graph.detect.graphics) on a synthetic panning clip with a logo."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.detect.detector import Detections
from broadtrack_graph.detect.graphics import StaticGraphics, mask_graphics


def clip_with_logo(frames=60, h=180, w=320):
    rng = np.random.default_rng(0)
    scene = np.clip(rng.normal(110, 40, (h, w + 6 * frames, 3)), 0, 255).astype(np.uint8)
    out = []
    for t in range(frames):
        image = np.ascontiguousarray(scene[:, 6 * t:6 * t + w])
        image[10:40, 20:90] = 20  # the logo box ...
        for x in range(30, 80, 8):
            image[18:32, x:x + 3] = 240  # ... with bright letters
        image[24:26, 30:80] = 240
        out.append(image)
    return out


def test_a_fixed_logo_is_masked_and_the_scene_is_not():
    graphics = StaticGraphics()
    for image in clip_with_logo():
        mask = graphics.update(image)
    assert mask is not None
    h, w = mask.shape
    logo = mask[int(10 * h / 180):int(40 * h / 180), int(20 * w / 320):int(90 * w / 320)]
    assert logo.mean() > 0.9
    outside = mask.copy()
    outside[:int(45 * h / 180), :int(95 * w / 320)] = False
    assert outside.mean() < 0.02


def test_mask_graphics_drops_points_and_mask_pixels_under_it():
    field = np.ones((90, 160), bool)
    detections = Detections(320, 180, lines_px={"Middle line": np.array([[30.0, 20.0], [200.0, 100.0]])},
                            marking_points_px=np.array([[30.0, 20.0], [200.0, 100.0]]), field_mask=field,
                            marking_mask=np.ones((180, 320), bool))  # the masks at two sizes
    mask = np.zeros((45, 80), bool)
    mask[0:12, 0:25] = True  # covers (30, 20) in frame pixels
    out = mask_graphics(detections, mask)
    assert out.marking_points_px.tolist() == [[200.0, 100.0]]
    assert out.lines_px["Middle line"].tolist() == [[200.0, 100.0]]
    assert not out.field_mask[5, 10] and out.field_mask[60, 100]
    assert not out.marking_mask[:48, :100].any() and out.marking_mask.sum() == 320 * 180 - 48 * 100
    assert mask_graphics(detections, None) is detections
