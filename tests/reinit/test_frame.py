"""The frame confidence's plausibility rule (broadtrack_graph.reinit.frame)."""

from __future__ import annotations

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves, TemplateSampling
from broadtrack_graph.reinit.frame import frame_confidence, plausible_position
from broadtrack_graph.types.observations import FrameObservations

PITCH = PitchTemplate()
CURVES = TemplateCurves(PITCH, line_step_m=1.0, circle_step_m=0.5)


def _lines_seen_by(camera: Camera) -> dict:
    """Labelled line points exactly where the camera projects each class."""
    out = {}
    for name, points in CURVES.samples_w.items():
        if not PITCH.is_on_ground(name):
            continue
        uv, front = camera.project(points)
        keep = front & camera.in_image(uv)
        if keep.sum() >= 4:
            out[name] = uv[keep]
    return out


def test_a_camera_over_the_pitch_has_no_confidence_however_well_it_fits():
    good = Camera.from_degrees(1000.0, 0.0, 0.0, 70.0, 0.0, (0.0, 55.0, -12.0), 960, 540)
    over = Camera.from_degrees(1000.0, 0.0, 0.0, 60.0, 0.0, (0.0, 30.0, -12.0), 960, 540)  # inside the touchlines
    scores = {}
    for name, camera in (("good", good), ("over", over)):
        observations = FrameObservations(0, 960, 540, lines_px=_lines_seen_by(camera))
        assert len(observations.lines_px) >= 2
        scores[name] = frame_confidence(camera, observations, None, CURVES, TemplateSampling(PITCH))
    assert scores["good"] > 0.9 and scores["over"] == 0.0  # both fit their points exactly
    assert not plausible_position((0.0, 30.0, -12.0), PITCH) and not plausible_position((0.0, 55.0, -0.5), PITCH)
    assert plausible_position((0.0, 55.0, -12.0), PITCH) and plausible_position((-75.0, 0.0, -24.0), PITCH)
    assert not plausible_position((-190.0, 0.0, -60.0), PITCH)  # out of the stadium: a fit slid along its sight line


def test_a_camera_a_few_metres_above_the_grass_is_not_a_broadcast_camera():
    """A focal point under MIN_CAMERA_HEIGHT_M (a grazing view, where grass texture lines up into faint runs) has no
    confidence however well it fits; the lowest synthetic presets (5.5 m) stand well above it."""
    from broadtrack_graph.reinit.frame import MIN_CAMERA_HEIGHT_M

    assert MIN_CAMERA_HEIGHT_M == 3.0
    assert not plausible_position((64.4, 16.4, -1.2), PITCH) and not plausible_position((0.0, 40.0, -2.9), PITCH)
    assert plausible_position((0.0, 40.0, -3.1), PITCH) and plausible_position((40.0, 40.0, -5.5), PITCH)
    low = Camera.from_degrees(1000.0, 0.0, 0.0, 87.0, 0.0, (0.0, 40.0, -2.0), 960, 540)
    observations = FrameObservations(0, 960, 540, lines_px=_lines_seen_by(low))
    assert len(observations.lines_px) >= 1
    assert frame_confidence(low, observations, None, CURVES, TemplateSampling(PITCH)) == 0.0
    higher = low.replace(position_m=(0.0, 40.0, -3.5))
    observations = FrameObservations(0, 960, 540, lines_px=_lines_seen_by(higher))
    assert frame_confidence(higher, observations, None, CURVES, TemplateSampling(PITCH)) > 0.5
