"""Named broadcast looks: a :class:`~broadtrack_graph.synth.field_config.SampleConfig` per look, for any camera.

The field-model samples draw their appearance from one wide config; a benchmark wants a few recognisable
kinds of broadcast instead, each still varied within its kind. Every look here shades the ground per
pixel (:class:`~broadtrack_graph.synth.randomise.GroundShader`) and turns the renderer's own moving shadow
band and exposure drift off, so that what the look says is all there is:

* ``clean``: a top-flight broadcast: even, mown grass (stripes along the length, a checkerboard or none),
  bright markings 10-14 cm wide, mild optics and sensor noise, no graphics, no compression artefacts.
* ``lower-league``: a small ground: worn grass and faint, narrow paint (6-11 cm, 60-85 % of clean white),
  artificial turf with other sports' lines on two frames in five, floodlight pools, a camera of lower
  resolution (rendered 360-576 px high and resized), soft, noisy and JPEG-compressed (quality 15-50).
* ``graphics``: ``clean`` with broadcast graphics (score bug, logo, ticker, ...) and, on half the frames,
  JPEG at quality 40-90.
* ``shadows``: ``clean`` with a stand's hard shadow edge across the pitch (30-60 % darker in the shade).
* ``blur``: ``clean`` with motion blur of a camera panning at 10-45 deg/s and a softer lens.

:func:`draw_named_look` draws one frame's look; :func:`broadtrack_graph.synth.field_samples.render_look`
renders a camera with it. No I/O here.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from broadtrack_graph.synth.field_config import SampleConfig
from broadtrack_graph.synth.field_look import Look, draw_look
from broadtrack_graph.synth.render import RenderSettings

_CLEAN = SampleConfig.plain(
    render_settings=RenderSettings(shadow=False, exposure_drift=0.0),
    grass_hue_shift_range=(-4.0, 6.0), grass_saturation_range=(0.85, 1.15), grass_value_range=(0.85, 1.1),
    stripe_patterns=("length", "length", "checker", "none"), stripe_count_range=(12, 22),
    stripe_contrast_range=(0.03, 0.1), wear_range=(0.0, 0.15), line_width_range_m=(0.10, 0.14),
    line_brightness_range=(0.9, 1.05), board_recolour_share=0.5, crowd_recolour_share=0.5,
    exposure_range=(0.9, 1.1), white_balance_range=(0.95, 1.05), gamma_range=(0.9, 1.1),
    lens_blur_range_px=(0.3, 0.8), sharpen_range=(0.3, 0.7), vignetting_range=(0.0, 0.2),
    noise_sigma_range=(1.0, 3.0),
)

NAMED_LOOKS: dict[str, SampleConfig] = {
    "clean": _CLEAN,
    "lower-league": dataclasses.replace(
        _CLEAN, render_height_range_px=(360, 576), grass_hue_shift_range=(-10.0, 14.0),
        grass_saturation_range=(0.5, 1.2), grass_value_range=(0.6, 1.2), stripe_patterns=("none", "length", "width"),
        stripe_count_range=(6, 14), stripe_contrast_range=(0.02, 0.06), wear_range=(0.4, 0.9), turf_share=0.4,
        line_width_range_m=(0.06, 0.11), line_brightness_range=(0.6, 0.85), floodlight_range=(0.1, 0.35),
        exposure_range=(0.75, 1.25), white_balance_range=(0.9, 1.1), gamma_range=(0.8, 1.25),
        lens_blur_range_px=(0.8, 1.6), sharpen_range=(0.0, 0.3), vignetting_range=(0.1, 0.35),
        noise_sigma_range=(2.0, 6.0), jpeg_share=1.0, jpeg_quality_range=(15, 50)),
    "graphics": dataclasses.replace(_CLEAN, graphics_share=1.0, jpeg_share=0.5, jpeg_quality_range=(40, 90)),
    "shadows": dataclasses.replace(_CLEAN, shadow_share=1.0, shadow_darkness_range=(0.3, 0.6)),
    "blur": dataclasses.replace(_CLEAN, motion_blur_share=1.0, pan_speed_range_deg_s=(10.0, 45.0),
                                lens_blur_range_px=(1.0, 1.8)),
}
"""Look name -> the switches its frames are drawn with (module docstring)."""

LOOK_NAMES: tuple[str, ...] = tuple(NAMED_LOOKS)


def named_look(name: str) -> SampleConfig:
    """The config of a named look; ValueError listing the names otherwise."""
    try:
        return NAMED_LOOKS[name]
    except KeyError:
        raise ValueError(f"unknown look '{name}'; choose from {list(LOOK_NAMES)}") from None


def draw_named_look(name: str, rng: np.random.Generator, centre_w: np.ndarray) -> Look:
    """One frame's appearance under a named look.

    Args:
        name: a :data:`NAMED_LOOKS` name.
        rng: the frame's appearance stream.
        centre_w: (3,) the ground point at the image centre, metres (where a shadow edge is placed).
    """
    return draw_look(rng, named_look(name), np.asarray(centre_w, float), True)
