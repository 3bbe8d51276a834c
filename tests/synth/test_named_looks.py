"""Named looks: each draws the effects its name says, and any camera renders under it at its own size."""

from __future__ import annotations

import math

import numpy as np
import pytest

from broadtrack_graph.geometry.aim import aim_angles
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.synth.field_samples import render_look
from broadtrack_graph.synth.named_looks import LOOK_NAMES, draw_named_look, named_look

AIM = np.array([10.0, 5.0, 0.0])


def draws(name: str, count: int = 12):
    return [draw_named_look(name, np.random.default_rng([i, 4]), AIM) for i in range(count)]


def test_each_look_draws_its_effects():
    assert LOOK_NAMES == ("clean", "lower-league", "graphics", "shadows", "blur")
    for look in draws("clean"):
        assert look.shadow is None and look.pan_speed_deg_s is None and not look.graphics
        assert look.jpeg_quality is None and look.render_height_px is None and not look.turf
    for look in draws("lower-league"):
        assert look.jpeg_quality is not None and look.jpeg_quality <= 50 and 360 <= look.render_height_px <= 576
        assert look.wear >= 0.4 and 2 * look.line_half_width_m <= 0.11
    assert all(look.graphics for look in draws("graphics"))
    assert all(look.shadow is not None for look in draws("shadows"))
    assert all(look.pan_speed_deg_s is not None and look.pan_speed_deg_s >= 10 for look in draws("blur"))
    with pytest.raises(ValueError, match="unknown look"):
        named_look("night")


def test_a_camera_renders_under_every_look_at_its_size():
    W, H = 320, 180
    position = np.array([0.0, 60.0, -18.0])
    pan, tilt = aim_angles(position, AIM)
    camera = Camera(W / 2 / math.tan(math.radians(40) / 2), 0.03, pan, tilt, 0.0, position, W, H)
    images = {}
    for name in LOOK_NAMES:
        look = draw_named_look(name, np.random.default_rng(1), AIM)
        rendered = render_look(camera, None, look, named_look(name))
        assert rendered.image.shape == (H, W, 3) and rendered.image.dtype == np.uint8
        assert rendered.labels.shape == (rendered.render_camera.height_px, rendered.render_camera.width_px)
        assert (rendered.hidden is not None) == look.graphics
        images[name] = rendered.image
    again = render_look(camera, None, draw_named_look("blur", np.random.default_rng(1), AIM), named_look("blur"))
    assert np.array_equal(again.image, images["blur"]), "the same look renders the same frame"
    assert not np.array_equal(images["clean"], images["shadows"])


def test_a_clips_later_frame_draws_its_noise_afresh_and_nothing_else():
    W, H = 320, 180
    position = np.array([0.0, 60.0, -18.0])
    pan, tilt = aim_angles(position, AIM)
    camera = Camera(W / 2 / math.tan(math.radians(40) / 2), 0.0, pan, tilt, 0.0, position, W, H)
    look = draw_named_look("clean", np.random.default_rng(1), AIM)
    first = render_look(camera, None, look, named_look("clean")).image
    assert np.array_equal(first, render_look(camera, None, look, named_look("clean"), frame=0).image)
    later = render_look(camera, None, look, named_look("clean"), frame=1).image
    assert np.array_equal(later, render_look(camera, None, look, named_look("clean"), frame=1).image)
    difference = first.astype(float) - later.astype(float)
    # Two draws of the sensor noise: independent, so their difference spreads sqrt(2) times the noise's sigma (the
    # grey levels clipped at 0 and 255 aside); the scene under it is the same.
    assert look.noise_sigma > 0.5
    assert abs(difference.std() - math.sqrt(2.0) * look.noise_sigma) < 0.35 * look.noise_sigma
    assert abs(difference.mean()) < 0.2
