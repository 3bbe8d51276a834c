"""Offline back-fill (broadtrack_graph.track.backfill) on frames drawn here."""

from __future__ import annotations

import numpy as np
from drawn_frames import draw_frame

from broadtrack_graph.detect.weightfree import WeightFreeDetector
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves, TemplateSampling
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.reinit.frame import frame_confidence
from broadtrack_graph.track.backfill import Backfill, PackedMarkings
from broadtrack_graph.types.status import FrameStatus
from broadtrack_graph.types.track_record import TrackRecord

W, H = 960, 540
PITCH = PitchTemplate()
CURVES = TemplateCurves(PITCH, line_step_m=1.0, circle_step_m=0.5)


def _camera(pan_deg):
    return Camera.from_degrees(1050.0, 0.0, pan_deg, 74.0, 0.0, (0.0, 55.0, -12.0), W, H)


def _backfill(detector, threshold=0.5, max_frames=10):
    return Backfill(detector.name, frame_confidence, PITCH, CURVES, TemplateSampling(PITCH), GraphConfig(), threshold,
                    max_frames, lambda camera_id: None)


def _frame(i, camera, shot_cut=False):
    from types import SimpleNamespace

    image, _ = draw_frame(camera, seed=i)
    return SimpleNamespace(frame_index=i, markings=DETECTOR.find_markings(image),
                           shot=SimpleNamespace(cut=shot_cut, is_other_view=False))


DETECTOR = WeightFreeDetector(PITCH)


def _error_px(a: Camera, b: Camera) -> float:
    points = np.vstack(list(PITCH.sample_uniform(2.0).values()))
    uv_a, front_a = a.project(points)
    uv_b, front_b = b.project(points)
    seen = front_a & front_b & b.in_image(uv_b)
    return float(np.median(np.linalg.norm(uv_a[seen] - uv_b[seen], axis=1)))


def test_packed_markings_name_as_the_markings_do():
    camera = _camera(-5.0)
    found = DETECTOR.find_markings(draw_frame(camera)[0])
    packed = PackedMarkings.pack(found)
    assert len(packed.masks) == 3  # marking, field and player masks at one bit a pixel
    assert sum(bits.nbytes for bits, _ in packed.masks.values()) == 3 * found.unnamed.marking_mask.size // 8
    from broadtrack_graph.detect.detector import PredictedCamera

    direct, again = DETECTOR.name(found, PredictedCamera(camera, 3.0)), DETECTOR.name(packed.found(), PredictedCamera(camera, 3.0))
    assert direct.lines_px.keys() == again.lines_px.keys() and len(direct.lines_px) >= 3
    for name in direct.lines_px:
        np.testing.assert_array_equal(direct.lines_px[name], again.lines_px[name])
    np.testing.assert_array_equal(direct.marking_mask, again.marking_mask)


def test_a_gap_before_the_first_lock_is_walked_back_from_it():
    truths = [_camera(-6.0 + 0.4 * i) for i in range(5)]
    backfill = _backfill(DETECTOR)
    for i in range(4):  # frames 0-3: no camera found yet
        frame = _frame(i, truths[i])
        backfill.note(frame)
        backfill.final(TrackRecord(i, f"{i + 1:06d}", None, None, status=FrameStatus.UNPLACED))
    frame = _frame(4, truths[4])
    backfill.note(frame)
    backfill.final(TrackRecord(4, "000005", None, truths[4], status=FrameStatus.TRACKED, camera_id="main"))
    assert sorted(backfill.recovered) == [0, 1, 2, 3]
    for i, found in backfill.recovered.items():
        assert found.source == 4 and found.camera_id == "main" and found.confidence >= 0.5
        assert 0.0 <= _error_px(found.camera, truths[i]) < 1.0, i
        assert found.observations.lines_px and found.observations.marking_mask is None


def test_nothing_is_walked_across_another_view_or_a_gap_too_long():
    truths = [_camera(-6.0 + 0.4 * i) for i in range(4)]
    backfill = _backfill(DETECTOR, max_frames=2)
    backfill.note(_frame(0, truths[0]))
    backfill.final(TrackRecord(0, "000001", None, None, status=FrameStatus.UNPLACED))
    backfill.final(TrackRecord(1, "000002", None, None, status=FrameStatus.OTHER_VIEW))  # a close-up between
    backfill.note(_frame(2, truths[2]))
    backfill.final(TrackRecord(2, "000003", None, truths[2], status=FrameStatus.TRACKED))
    assert backfill.recovered == {}
    for i in range(3, 6):  # three frames: longer than max_frames, dropped as it grows
        backfill.note(_frame(i, truths[3]))
        backfill.final(TrackRecord(i, f"{i + 1:06d}", None, None, status=FrameStatus.UNPLACED))
    backfill.finish()
    assert backfill.recovered == {} and backfill.seconds > 0


def test_a_walk_stops_at_the_first_frame_that_is_not_confident():
    truth = _camera(-5.0)
    backfill = _backfill(DETECTOR)
    wrong = Camera.from_degrees(2600.0, 0.0, 12.0, 70.0, 0.0, (0.0, 55.0, -12.0), W, H)  # frame 0: another view
    backfill.note(_frame(0, wrong))
    backfill.final(TrackRecord(0, "000001", None, None, status=FrameStatus.UNPLACED))
    backfill.note(_frame(1, truth))
    backfill.final(TrackRecord(1, "000002", None, None, status=FrameStatus.UNPLACED))
    backfill.note(_frame(2, truth))
    backfill.final(TrackRecord(2, "000003", None, truth, status=FrameStatus.TRACKED))
    assert sorted(backfill.recovered) == [1]
