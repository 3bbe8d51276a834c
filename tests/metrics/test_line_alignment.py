"""The alignment check of real-video runs, on frames drawn from a known camera."""

from __future__ import annotations

import math

from drawn_frames import draw_frame

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves
from broadtrack_graph.metrics.line_alignment import AlignmentConfig, line_alignment

CONFIG = AlignmentConfig()
CURVES = TemplateCurves(PitchTemplate(), line_step_m=1.0, circle_step_m=0.5)


def _camera(**change):
    camera = Camera.from_degrees(700.0, 0.0, 0.0, 74.0, 0.0, (0.0, 55.0, -12.0), 640, 360)
    return camera.replace(**change) if change else camera


def test_the_true_camera_is_aligned_on_every_marking():
    image, _ = draw_frame(_camera(), players=0)
    alignment = line_alignment(image, _camera(), CURVES, CONFIG)
    assert alignment.all_markings > 0.9 and alignment.visible_markings > 0.9
    assert alignment.aligned(CONFIG)
    assert alignment.visible_samples > 0.9 * alignment.samples


def test_a_marking_the_frame_does_not_show_fails_only_the_all_markings_share():
    truth = _camera()
    image, _ = draw_frame(truth, players=0, hidden=("Side line top",))
    alignment = line_alignment(image, truth, CURVES, CONFIG)
    assert alignment.all_markings < CONFIG.aligned_share  # the far touchline is a third of the samples
    assert alignment.visible_markings > 0.9 and alignment.aligned(CONFIG)


def test_cameras_off_by_a_fraction_of_a_degree_are_not_aligned():
    truth = _camera()
    changes = ({"tilt_rad": truth.tilt_rad + math.radians(0.3)}, {"tilt_rad": truth.tilt_rad - math.radians(0.3)},
               {"pan_rad": truth.pan_rad + math.radians(0.5)})
    for hidden in ((), ("Side line top",)):
        image, _ = draw_frame(truth, players=0, hidden=hidden)
        for change in changes:
            assert not line_alignment(image, truth.replace(**change), CURVES, CONFIG).aligned(CONFIG), (hidden, change)
    # A zoom error moves markings in proportion to their distance from the image centre: the far
    # touchline shows it; with that line hidden, the centre circle alone does not (a known blind spot).
    image, _ = draw_frame(truth, players=0)
    assert not line_alignment(image, truth.replace(focal_px=truth.focal_px * 1.05), CURVES, CONFIG).aligned(CONFIG)


def test_markings_on_bare_grass_are_too_few_visible_ones_to_pass():
    truth = _camera()
    image, _ = draw_frame(truth, players=0, hidden=tuple(CURVES.samples_w))
    alignment = line_alignment(image, truth, CURVES, CONFIG)
    assert alignment.visible_samples == 0 and alignment.visible_markings == 0.0
    assert not alignment.aligned(CONFIG)


def test_a_camera_showing_no_grass_is_not_scored():
    truth = _camera()
    image, _ = draw_frame(truth, players=0)
    assert line_alignment(image, truth.replace(tilt_rad=math.radians(120.0)), CURVES, CONFIG) is None


def test_line_pixels_computed_once_give_the_same_shares():
    from broadtrack_graph.metrics.line_alignment import line_pixels

    truth = _camera()
    image, _ = draw_frame(truth, players=0)
    pixels = line_pixels(image, CONFIG)
    for camera in (truth, truth.replace(tilt_rad=truth.tilt_rad + math.radians(0.3))):
        assert line_alignment(image, camera, CURVES, CONFIG, pixels) == line_alignment(image, camera, CURVES, CONFIG)
