"""Frames prepared ahead of the tracking (track/ahead.py): where they are prepared, and the same frames either way."""

import subprocess
import sys

import numpy as np
import pytest

from broadtrack_graph.detect.weightfree import WeightFreeDetector
from broadtrack_graph.io.frames import open_frames
from broadtrack_graph.io.prefetch import PREFETCH_ENV
from broadtrack_graph.synth.writer import write_synthetic_clip
from broadtrack_graph.track import ahead
from broadtrack_graph.track.ahead import (
    FramesAhead,
    FramesInProcess,
    FramesRecipe,
    feed_in_process,
    slot_bytes,
    without_pixels,
)
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.inputs import FrameInput, frames_from_source
from broadtrack_graph.track.shot_stream import ShotStream

FRAMES = 8
SIZE = (1280, 720)


@pytest.fixture(scope="module")
def clip(tmp_path_factory):
    out = tmp_path_factory.mktemp("ahead") / "clip"
    write_synthetic_clip(out, preset="main", frame_count=FRAMES, width_px=SIZE[0], height_px=SIZE[1], seed=4,
                         write_masks=False, progress=False)
    return out


@pytest.fixture
def recipe(clip):
    with open_frames(clip) as source:
        return FramesRecipe.of(source)


def test_a_long_input_read_from_a_file_is_prepared_in_a_process(recipe, monkeypatch):
    monkeypatch.delenv(PREFETCH_ENV, raising=False)
    detector = WeightFreeDetector()
    monkeypatch.setattr(ahead, "PROCESS_MIN_FRAMES", FRAMES)
    monkeypatch.setattr(ahead.os, "cpu_count", lambda: 2)
    monkeypatch.setattr(ahead, "shared_memory_free", lambda: 10 ** 10)
    assert feed_in_process(recipe, detector, FRAMES, SIZE)
    assert not feed_in_process(recipe, detector, FRAMES - 1, SIZE)  # too short to pay for the process's start
    assert not feed_in_process(None, detector, FRAMES, SIZE)  # frames in memory: nothing to open again
    assert not feed_in_process(recipe, None, FRAMES, SIZE)  # a detections file's frames
    assert not feed_in_process(recipe, object(), FRAMES, SIZE)  # a detector that finds nothing ahead
    monkeypatch.setattr(ahead.os, "cpu_count", lambda: 1)
    assert not feed_in_process(recipe, detector, FRAMES, SIZE)  # one core: nothing to overlap
    monkeypatch.setattr(ahead.os, "cpu_count", lambda: 2)
    monkeypatch.setattr(ahead, "shared_memory_free", lambda: 2 * ahead.PROCESS_DEPTH * slot_bytes(*SIZE) - 1)
    assert not feed_in_process(recipe, detector, FRAMES, SIZE)  # a container's small shared memory
    monkeypatch.setattr(ahead, "shared_memory_free", lambda: 10 ** 10)
    for value in ("thread", "0"):
        monkeypatch.setenv(PREFETCH_ENV, value)
        assert not feed_in_process(recipe, detector, FRAMES, SIZE)


def test_the_process_prepares_the_frames_a_thread_would(recipe):
    config, detector = TrackingConfig(), WeightFreeDetector()
    in_process = FramesInProcess(recipe, detector, config, 1, SIZE)
    got = list(in_process)
    with open_frames(recipe.path) as source:
        here = FramesAhead(config, detector.find_markings, lambda: 0)  # never ahead: no flow ahead
        stream = ShotStream(frames_from_source(source), reduce=detector.area_working_image)
        expected = [here(frame) for frame in stream]
    assert [f.frame_index for f in got] == list(range(FRAMES))
    for a, b in zip(got, expected):
        assert np.array_equal(a.image, b.image)
        assert np.array_equal(a.flow_frame.grey, b.flow_frame.grey)
        assert np.array_equal(a.markings.points_work_px, b.markings.points_work_px)
        assert np.array_equal(a.markings.unnamed.marking_mask, b.markings.unnamed.marking_mask)
        assert np.array_equal(a.graphics_mask, b.graphics_mask) and a.shot == b.shot
        assert a.working_bgr is None and a.repeats_previous == b.repeats_previous
    assert in_process.detects_shots and in_process.shots == stream.shots


def test_the_flow_is_tracked_ahead_only_while_that_side_is_far_enough_ahead(recipe):
    config, detector = TrackingConfig(), WeightFreeDetector()
    taken = [0]
    prepare = FramesAhead(config, detector.find_markings, lambda: taken[0])
    with open_frames(recipe.path) as source:
        frames = list(ShotStream(frames_from_source(source), reduce=detector.area_working_image))
    made = [prepare(frame) for frame in frames[:4]]  # the loop has taken none: 0, 1, 2, 3 frames ahead
    assert [f.flow_ahead is not None for f in made] == [False, False, True, True]  # the first has no previous frame
    taken[0] = 4
    assert prepare(frames[4]).flow_ahead is None  # caught up: the loop tracks it


def test_the_flow_tracked_ahead_in_another_process_is_the_loops_own(clip, recipe):
    # A process sends each frame's copy apart: the flow's copy of the previous image is not the object the loop
    # holds, but the same image; the loop takes the flow found ahead, the very matches it would track itself.
    import pickle

    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.io.cameras import read_camera_file
    from broadtrack_graph.track.observe import FrameObserver

    config, detector = TrackingConfig(), WeightFreeDetector()
    prepare = FramesAhead(config, detector.find_markings, lambda: -10)  # always far enough ahead
    with open_frames(recipe.path) as source:
        frames = [pickle.loads(pickle.dumps(prepare(frame)))
                  for frame in ShotStream(frames_from_source(source), reduce=detector.area_working_image)]
    assert all(f.flow_ahead is not None for f in frames[1:])
    cameras = [read_camera_file(clip / "cameras" / f"camera_{i + 1:06d}.json") for i in range(FRAMES)]
    timings = {"detect_s": 0.0, "flow_s": 0.0, "markings_ahead_s": 0.0}
    loop = FrameObserver(detector, config, *SIZE, PitchTemplate(), {}, timings)
    own = FrameObserver(detector, config, *SIZE, PitchTemplate(), {}, dict(timings))
    for i, frame in enumerate(frames):
        previous = cameras[i - 1] if i else None
        if i:
            assert frame.flow_ahead.prev_frame is not frames[i - 1].flow_frame  # a copy of its own
            assert loop._flow_ahead_applies(frame.flow_ahead)
        observations, _ = loop.observe(frame, None, previous)
        frame.flow_ahead = None  # the loop tracks the flow itself
        tracked, _ = own.observe(frame, None, previous)
        if i:
            assert len(tracked.flow) > 50
            assert np.array_equal(observations.flow.uv_prev_px, tracked.flow.uv_prev_px)
            assert np.array_equal(observations.flow.uv_cur_px, tracked.flow.uv_cur_px)


def test_the_pixels_stay_where_the_loop_reads_none_of_them(recipe):
    config, detector = TrackingConfig(), WeightFreeDetector()
    sent = list(FramesInProcess(recipe, detector, config, 1, SIZE, send_pixels=False))
    with_pixels = list(FramesInProcess(recipe, detector, config, 1, SIZE))
    assert all(f.image is None and f.image_stayed and f.has_image for f in sent)  # markings and flow made there
    assert all(f.image is not None and not f.image_stayed for f in with_pixels)
    for a, b in zip(sent, with_pixels):
        assert np.array_equal(a.markings.points_work_px, b.markings.points_work_px)
        assert np.array_equal(a.flow_frame.grey, b.flow_frame.grey)


def test_a_frame_keeps_its_pixels_while_the_loop_may_read_them():
    class Shot:
        def __init__(self, other):
            self.is_other_view = other

    image, found, flow = np.zeros((4, 6, 3), np.uint8), object(), object()

    def frame(**fields):
        return FrameInput(0, "000001", 0.0, image, **fields)

    assert frame(markings=found, flow_frame=flow).image is image  # untouched until asked
    kept = [without_pixels(frame(), True),  # nothing found ahead: the loop detects on the image
            without_pixels(frame(markings=found), True),  # no flow frame: the loop makes it from the image
            without_pixels(frame(flow_frame=flow, shot=Shot(False)), True),
            without_pixels(frame(shot=Shot(True)), True)]  # another view: the court model may look at it
    assert all(f.image is image and not f.image_stayed for f in kept)
    left = [without_pixels(frame(markings=found, flow_frame=flow), True),
            without_pixels(frame(markings=found), False),  # a run without flow
            without_pixels(frame(markings=found, flow_frame=flow, shot=Shot(True)), True)]
    assert all(f.image is None and f.image_stayed and f.has_image for f in left)
    missing = without_pixels(FrameInput(0, "000001", 0.0, None, problem="cannot be decoded"), True)
    assert not missing.has_image and not missing.image_stayed


PREPARING_SIDE = """
import sys
from broadtrack_graph.detect.weightfree import WeightFreeDetector
from broadtrack_graph.io.frames import open_frames
from broadtrack_graph.track.ahead import FramesRecipe, _prepared_frames
from broadtrack_graph.track.config import TrackingConfig
with open_frames(sys.argv[1]) as source:
    recipe = FramesRecipe.of(source)
prepared = list(_prepared_frames(recipe, WeightFreeDetector(), TrackingConfig(), 1, True, lambda: 0))
assert all(frame.markings is not None for frame in prepared), "markings not found"
print(" ".join(sorted({name.split(".")[0] for name in sys.modules} & {"scipy", "gtsam", "onnxruntime"})))
"""


def test_the_preparing_side_starts_without_the_solver_or_scipy(clip):
    """The preparing process imports what finding the markings needs, not GTSAM or scipy (each a fraction of a
    second a run would wait for its first frame)."""
    done = subprocess.run([sys.executable, "-c", PREPARING_SIDE, str(clip)], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.strip() == ""


def test_a_frame_read_as_another_view_has_its_markings_found_by_the_loop_as_ahead(recipe):
    """The preparing side leaves a frame read as another view its pixels and no markings; the loop, when it looks at
    it, finds them and keeps them on the frame (its faint look reads them there): the detections are those found
    ahead."""
    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.track.observe import FrameObserver

    class OtherView:
        is_other_view, cut, kind, reason = True, False, "close-up", "a stand-in"

    config, detector = TrackingConfig(), WeightFreeDetector()
    prepare = FramesAhead(config, detector.find_markings, lambda: 0)
    with open_frames(recipe.path) as source:
        frame = next(iter(frames_from_source(source)))
    ahead = prepare(FrameInput(0, "000001", 0.0, frame.image.copy()))
    frame.shot = OtherView()
    left = without_pixels(prepare(frame), True)
    assert left.markings is None and left.image is not None
    observer = FrameObserver(detector, config, *SIZE, PitchTemplate(), {},
                             {"detect_s": 0.0, "flow_s": 0.0, "markings_ahead_s": 0.0})
    found = observer.detect(left, None)
    assert left.markings is not None
    assert np.array_equal(found.marking_mask, detector.name(ahead.markings).marking_mask)
    assert np.array_equal(left.markings.points_work_px, ahead.markings.points_work_px)
