"""The per-frame state machine (broadtrack_graph.track.frame_loop) with fakes: a scripted solver,
re-initialisation and confidence (no GTSAM, no images to detect on). Records are read back
from the run folder."""

from __future__ import annotations

import numpy as np
import pytest

from broadtrack_graph.detect.detector import Detections
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.estimates import FrameEstimate
from broadtrack_graph.io.run_folder import read_track
from broadtrack_graph.reinit.scoring import ReinitResult
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.frame_loop import TrackingRun
from broadtrack_graph.track.inputs import FrameInput
from broadtrack_graph.track.run_context import RunContext
from broadtrack_graph.types.observations import FlowMatches, FrameObservations

W, H = 1920, 1080
LINES = {"Middle line": np.array([[900.0, 100.0 + 50 * i] for i in range(6)])}


def camera(pan_rad: float) -> Camera:
    return Camera(2000.0, 0.0, pan_rad, 1.3, 0.0, (0.0, 55.0, -12.0), W, H)


def solved(i: int) -> Camera:
    """What the fake solver estimates for frame i (without a guess)."""
    return camera(0.01 * i)


def reinit_camera(i: int) -> Camera:
    """What the fake re-initialisation finds for frame i."""
    return camera(-0.01 * i)


HELD_TRIPOD = Tripod((0.0, 60.0, -15.0), 0.2)  # a tripod held by the solver (the judge's rule 7 does not apply)


class FakeSolver:
    """A streaming solver that releases frame t after frame t + lag (lag 0: at once).

    Returns the guess, else ``solved(i)``; ``lost`` frames get no camera. With ``smooth``,
    released cameras differ from the current ones (as a smoother's do). With ``held_tripod``, that tripod holds
    every frame's focal point whatever the run sets (the judge's rule 7 never holds a camera back).
    """

    def __init__(self, lag: int = 0, lost=(), smooth: bool = False, held_tripod: Tripod | None = None) -> None:
        self.lag, self.lost, self.smooth = lag, set(lost), smooth
        self.pushed, self.resets, self.replaced, self.held, self.holds = [], [], [], [], []
        self.held_tripod, self._tripod = held_tripod, None
        self.rebuilds = 0

    @property
    def tripod(self):
        return self.held_tripod or self._tripod

    @tripod.setter
    def tripod(self, tripod):
        self._tripod = tripod

    def push(self, observations, guess, trust_previous, fallback=None):
        i = observations.frame_index
        self.pushed.append((i, guess is not None, trust_previous, observations.flow is not None))
        current = FrameEstimate(i, None if i in self.lost else (guess or solved(i)), reason="scripted loss")
        self.held.append(current)
        released = []
        while len(self.held) > self.lag:
            released.append(self._released(self.held.pop(0)))
        return current, released

    def _released(self, estimate):
        if self.smooth and estimate.camera is not None:
            return FrameEstimate(estimate.frame_index, estimate.camera.replace(roll_rad=0.001))
        return estimate

    def reset(self, camera):
        self.resets.append(camera)

    def replace_last(self, camera):
        self.replaced.append(camera)

    def hold_position_next(self):
        self.holds.append(len(self.pushed))  # the index of the next push

    def finish(self):
        out = [self._released(e) for e in self.held]
        self.held = []
        return out


class Scripted:
    """Fake re-initialisation and confidence, scripted per frame."""

    def __init__(self, fail=(), confidence=None, reinit_confidence=None) -> None:
        self.fail = set(fail)
        self.scores = confidence or {}
        self.reinit_scores = reinit_confidence or {}
        self.reinit_calls = []

    def reinitialise(self, observations, detections, pitch, positions, curves, sampling):
        i = observations.frame_index
        self.reinit_calls.append(i)
        if i in self.fail:
            return ReinitResult(None, None, "", "scripted failure")
        return ReinitResult(reinit_camera(i), None, "lines")

    def confidence(self, camera, observations, detections, curves, sampling):
        i = observations.frame_index
        if camera.roll_rad == 0.001:
            return 0.7  # a smoothed camera
        if np.isclose(camera.pan_rad, reinit_camera(i).pan_rad) and i:
            return self.reinit_scores.get(i, 0.9)
        return self.scores.get(i, 0.9)


def frame(i: int, observations: bool = True, image=None) -> FrameInput:
    flow = FlowMatches(np.zeros((10, 2)), np.zeros((10, 2)))
    obs = FrameObservations(i, W, H, lines_px=dict(LINES), flow=flow) if observations else None
    return FrameInput(i, f"{i + 1:06d}", i / 25.0, image=image, observations=obs)


NO_BUDGET = TrackingConfig(search_cost_frames=0.0)  # every lost frame may search (the budget has its own tests)


def run_of(tmp_path, solver, script, config=NO_BUDGET, **kwargs) -> TrackingRun:
    return TrackingRun(W, H, tmp_path / "run", RunContext(config, solver_factory=lambda *args: solver,
                                                          reinitialise=script.reinitialise,
                                                          confidence=script.confidence, **kwargs))


def statuses(tmp_path):
    return [(r.frame_index, r.status, r.reason) for r in read_track(tmp_path / "run").records]


def test_the_state_machine_frame_by_frame(tmp_path):
    solver = FakeSolver(lost={6})
    script = Scripted(fail={6, 7}, confidence={2: 0.3, 9: 0.1}, reinit_confidence={2: 0.8, 9: 0.05})
    run = run_of(tmp_path, solver, script)
    for i in range(11):
        run.process(frame(i, observations=i != 4))
    result = run.finish()
    assert statuses(tmp_path) == [
        (0, "reinitialised", None),  # first frame: lost, re-initialised
        (1, "tracked", None),
        (2, "reinitialised", None),  # confidence 0.3 < 0.5: re-initialised (0.8)
        (3, "tracked", None),
        (4, "missing-frame", "frame could not be read"),
        (5, "tracked", None),  # the track survives one missing frame
        (6, "failed", "scripted loss"),  # no camera and re-initialisation failed
        (7, "no-detections", "no camera found: global search: scripted failure"),
        (8, "reinitialised", None),
        (9, "failed", "confidence 0.10 below 0.20 and re-initialisation failed"),
        (10, "reinitialised", None),
    ]
    # (frame, with a guess, linked to the previous frame, with flow): a re-initialised frame is a
    # fresh start without flow; frame 7 never reached the solver.
    assert solver.pushed == [(0, True, False, False), (1, False, True, True), (2, False, True, True),
                             (3, False, True, True), (5, False, True, True), (6, False, True, True),
                             (8, True, False, False), (9, False, True, True), (10, True, False, False)]
    # A search that finds nothing confident at the known camera's position tries the default positions too (the
    # lost frames 6 and 7); the trusted chain's held camera (frame 9) is searched at its own position alone.
    assert script.reinit_calls == [0, 2, 6, 6, 7, 7, 8, 9, 10]
    # Restarts of the known, trusted camera (frames 8 and 10, pushes 6 and 8) hold its focal point; the first
    # camera of the run (frame 0) is placed by its markings.
    assert solver.holds == [6, 8]
    # Frame 2's camera, re-initialised after its update, is the camera frame 3 continues from (flow, motion prior);
    # as a new chain's, it predicts frame 3 alone (the replaced chain's motion is not its own).
    assert [c.to_vector().tolist() for c in solver.replaced] == [reinit_camera(2).to_vector().tolist()]
    assert solver.resets == []
    records = {r.frame_index: r for r in read_track(tmp_path / "run").records}
    assert records[2].camera.pan_rad == pytest.approx(reinit_camera(2).pan_rad, abs=1e-9)
    assert records[2].confidence == pytest.approx(0.8) and records[2].reinitialised
    assert records[3].camera.pan_rad == pytest.approx(solved(3).pan_rad, abs=1e-9)
    assert records[9].camera is None and records[9].confidence is None
    assert result.summary["status_counts"]["failed"] == 2 and result.summary["solver_restarts"] == 0


def test_a_new_chain_s_camera_replacing_the_solved_one_predicts_the_next_frame_alone(tmp_path):
    solver = FakeSolver()
    run = run_of(tmp_path, solver, Scripted(confidence={2: 0.3}, reinit_confidence={2: 0.8}))
    for i in range(3):
        run.process(frame(i))
    # The solved chain's motion (frames 0-1) is not the new camera's: no velocity from it into frame 3.
    assert len(run._history) == 1 and run._history[-1].pan_rad == pytest.approx(reinit_camera(2).pan_rad)
    run.process(frame(3))
    assert len(run._history) == 2
    run.finish()


def test_fixed_lag_records_are_written_in_frame_order_as_frames_are_released(tmp_path):
    solver = FakeSolver(lag=2, smooth=True)
    run = run_of(tmp_path, solver, Scripted())
    track_lines = []
    for i in range(6):
        run.process(frame(i, observations=i != 3))
        track_lines.append(len((tmp_path / "run" / "track.jsonl").read_text().splitlines()))
    # Frame 3 (missing) is final at once but waits for frames 1 and 2.
    assert track_lines == [0, 0, 1, 1, 2, 4]
    run.finish()
    records = read_track(tmp_path / "run").records
    assert [(r.frame_index, r.status) for r in records] == [
        (0, "reinitialised"), (1, "tracked"), (2, "tracked"), (3, "missing-frame"), (4, "tracked"), (5, "tracked")]
    # A released camera other than the one scored when the frame was added is scored again.
    assert all(r.confidence == 0.7 for r in records if r.camera is not None)
    assert all(r.camera.roll_rad == pytest.approx(0.001) for r in records if r.camera is not None)


def test_a_frame_never_released_is_failed_at_the_end(tmp_path):
    solver = FakeSolver(lag=2)
    solver.finish = lambda: []
    run = run_of(tmp_path, solver, Scripted())
    for i in range(3):
        run.process(frame(i))
    run.finish()
    assert statuses(tmp_path) == [(0, "reinitialised", None), (1, "failed", "no estimate released"),
                                  (2, "failed", "no estimate released")]


class FakeDetector:
    """Returns scripted detections per call; records the predicted camera it was given."""

    def __init__(self, empty=(), broken=(), with_map: bool = False) -> None:
        self.empty, self.broken = set(empty), set(broken)
        self.with_map = with_map  # detections carry a marking map (as the weight-free detector's do)
        self.predicted = []

    def detect(self, image, predicted=None):
        i = int(image[0, 0, 0])
        self.predicted.append((i, predicted))
        if i in self.broken:
            raise ValueError("image is not BGR")
        points = np.zeros((0, 2)) if i in self.empty else np.zeros((20, 2))
        lines = {} if i in self.empty else dict(LINES)
        return Detections(W, H, lines_px=lines, marking_points_px=points,
                          marking_mask=np.ones((9, 16), bool) if self.with_map else None)


def test_detector_frames_prediction_no_pitch_and_the_observer(tmp_path):
    detector = FakeDetector(empty={2}, broken={5})
    script = Scripted(fail={3})
    done = []
    run = run_of(tmp_path, FakeSolver(), script, TrackingConfig(use_flow=False), detector=detector,
                 on_frame_done=lambda f, handed, detections: done.append((f.frame_index, handed, detections)))
    for i in range(7):
        run.process(frame(i, observations=False, image=np.full((4, 4, 3), i, np.uint8)))
    run.finish()
    assert statuses(tmp_path) == [
        (0, "reinitialised", None), (1, "tracked", None),
        (2, "no-pitch", "no pitch in view"),
        (3, "unplaced", "no camera found: global search: scripted failure"),
        (4, "reinitialised", None),
        (5, "failed", "detector: image is not BGR"),
        (6, "reinitialised", None),
    ]
    # A prediction only while the previous frame is trusted (the chain is broken at 2, 3 and 5).
    predicted = {i: p for i, p in detector.predicted}
    assert [i for i, p in predicted.items() if p is not None] == [1, 2, 5]
    assert predicted[1].camera.pan_rad == pytest.approx(reinit_camera(0).pan_rad)
    assert predicted[1].uncertainty_px == 3.0
    # The observer sees every frame: what it handed the solver and its detections.
    assert [i for i, _, _ in done] == list(range(7))
    handed = {i: h for i, h, _ in done}
    assert [i for i, h in handed.items() if h is not None] == [0, 1, 4, 6]
    assert handed[1].lines_px.keys() == LINES.keys() and handed[1].flow is None
    detections = {i: d for i, _, d in done}
    assert detections[5] is None and detections[2] is not None and detections[3] is not None


def test_frames_without_detections_are_motion_prior_then_dropped(tmp_path):
    solver = FakeSolver()
    config = TrackingConfig(max_motion_prior_frames=3)
    run = run_of(tmp_path, solver, Scripted(), config=config)
    for i in range(10):
        empty = 2 <= i <= 7
        run.process(FrameInput(i, f"{i + 1:06d}", i / 25.0,
                               observations=FrameObservations(i, W, H, lines_px={} if empty else dict(LINES))))
    result = run.finish()
    got = [(index, status) for index, status, _ in statuses(tmp_path)]
    assert got == [(0, "reinitialised"), (1, "tracked"), (2, "motion-prior"), (3, "motion-prior"), (4, "motion-prior"),
                   (5, "no-detections"), (6, "no-detections"), (7, "no-detections"), (8, "reinitialised"),
                   (9, "tracked")]
    records = read_track(tmp_path / "run").records
    assert all(r.camera is None for r in records[2:5]) and "carried by the motion prior (1 of at most 3)" in records[2].reason
    counts = result.summary["status_counts"]
    assert counts["motion-prior"] == 3 and result.summary["frames_with_camera"] == 4
    assert result.summary["completeness"] == 0.4  # motion-prior frames never count toward completeness
    assert sorted(p.name for p in (tmp_path / "run" / "cameras").iterdir()) == [
        "camera_000001.json", "camera_000002.json", "camera_000009.json", "camera_000010.json"]


def test_interrupted_loop_leaves_a_truthful_summary(tmp_path):
    import json

    from broadtrack_graph.track.feed import run_loop

    def frames():
        for i in range(5):
            yield frame(i)
        raise KeyboardInterrupt

    run = run_of(tmp_path, FakeSolver(), Scripted(), progress=False)
    with pytest.raises(KeyboardInterrupt):
        run_loop(run, frames())
    summary = json.loads((tmp_path / "run" / "summary.json").read_text())
    lines = (tmp_path / "run" / "track.jsonl").read_text().splitlines()
    assert summary["interrupted"] is True and summary["complete"] is False
    assert summary["frames_written"] == len(lines) == 5 and summary["frames_with_camera"] == 5


def test_a_cut_breaks_the_chain_and_other_views_get_no_camera(tmp_path):
    from broadtrack_graph.shots.segmenter import FrameShot

    solver = FakeSolver()
    script = Scripted()
    run = run_of(tmp_path, solver, script)
    shots = {0: FrameShot(0, True, "main", ""), 3: FrameShot(1, True, "main", ""),
             5: FrameShot(2, True, "close-up", "huge blob"), 6: FrameShot(2, False, "close-up", "huge blob"),
             7: FrameShot(3, True, "main", "")}
    for i in range(9):
        f = frame(i)
        f.shot = shots.get(i, FrameShot(0, False, "main", ""))
        run.process(f)
    result = run.finish()
    got = statuses(tmp_path)
    assert [s for _, s, _ in got] == ["reinitialised", "tracked", "tracked", "reinitialised", "tracked",
                                      "other-view", "other-view", "reinitialised", "tracked"]
    assert got[5][2].startswith("other view (close-up)")
    # Frames 3 and 7 start shots: a fresh start with a guess, not linked to the frame before, no flow.
    by_frame = {p[0]: p for p in solver.pushed}
    assert by_frame[3] == (3, True, False, False) and by_frame[7] == (7, True, False, False)
    assert 5 not in by_frame and 6 not in by_frame
    assert result.summary["cuts"] == 3
    assert not (tmp_path / "run" / "cameras" / "camera_000006.json").exists()


def test_no_camera_is_written_before_the_first_confident_frame_of_a_marking_map_chain(tmp_path):
    script = Scripted(confidence={0: 0.3, 1: 0.4, 3: 0.4}, reinit_confidence={1: 0.35, 3: 0.3})

    def run_with(with_map: bool, folder, held_tripod=HELD_TRIPOD):
        solver = FakeSolver(held_tripod=held_tripod)
        # The scripted search is the camera from nothing (with the court model on, a map's new shot is not searched).
        config = TrackingConfig(use_flow=False, court_reinit=False)
        run = TrackingRun(W, H, folder, RunContext(config, FakeDetector(with_map=with_map),
                                                   solver_factory=lambda *args: solver,
                                                   reinitialise=script.reinitialise, confidence=script.confidence))
        for i in range(5):
            run.process(frame(i, observations=False, image=np.full((4, 4, 3), i, np.uint8)))
        run.finish()
        return read_track(folder).records, solver

    records, solver = run_with(True, tmp_path / "map")
    assert [(r.frame_index, r.status, r.camera is not None) for r in records] == [
        (0, "failed", False),  # re-initialised at 0.3: it seeds frame 1, it is not written
        (1, "failed", False),  # 0.4, the search finds no better (0.35): still no confident frame
        (2, "tracked", True),  # 0.9: the chain is trusted from here
        (3, "tracked", True),  # 0.4 in a trusted chain: written, with its confidence
        (4, "tracked", True),
    ]
    assert records[0].reason.endswith("no confident frame since the re-initialisation; camera not written")
    assert records[1].reason.startswith("confidence 0.40 below 0.60")  # a new camera: trusted from 0.5 + the margin
    assert records[3].confidence == pytest.approx(0.4)
    assert [p[0] for p in solver.pushed] == [0, 1, 2, 3, 4]  # the unwritten cameras still seeded the solver
    # Labelled lines without a marking map: the same confidences are written (lines name what they show).
    records, _ = run_with(False, tmp_path / "lines")
    assert all(r.camera is not None for r in records)
    # No tripod holding the focal point: frame 3 (0.4) is held back too, the chain having 1 of its 4 frames at the
    # tripod's bar (0.6); the chain goes on (frame 4, 0.9, written).
    records, _ = run_with(True, tmp_path / "no-tripod", held_tripod=None)
    assert [(r.frame_index, r.camera is not None) for r in records] == [(0, False), (1, False), (2, True), (3, False),
                                                                       (4, True)]
    assert records[3].reason == ("confidence 0.40 below 0.60 with no tripod holding the focal point, most of the "
                                 "chain's frames under it; camera not written")


def test_a_trusted_chain_switches_only_to_a_camera_clearly_better_confident_or_not(tmp_path):
    solver = FakeSolver(held_tripod=HELD_TRIPOD)
    script = Scripted(confidence={2: 0.45, 15: 0.45}, reinit_confidence={2: 0.52, 15: 0.58})
    run = run_of(tmp_path, solver, script)
    for i in range(16):
        run.process(frame(i))
    run.finish()
    records = {r.frame_index: r for r in read_track(tmp_path / "run").records}
    assert script.reinit_calls == [0, 2, 15]  # frame 2: the known camera's position, confident: the search ends
    # 0.52 is over the threshold but not the margin (0.1) better than the held 0.45: the held camera stays.
    assert records[2].status == "tracked" and records[2].confidence == pytest.approx(0.45)
    assert records[15].status == "reinitialised" and records[15].confidence == pytest.approx(0.58)  # by the margin
    assert len(solver.replaced) == 1 and solver.resets == []


def test_each_shot_gets_its_camera_s_id_and_a_returning_camera_its_own(tmp_path):
    import json

    from broadtrack_graph.shots.segmenter import FrameShot

    corner = Camera(4400.0, 0.0, -0.1, 1.25, 0.0, (53.0, 70.0, -22.0), W, H)

    class TwoCameras(Scripted):
        def reinitialise(self, observations, detections, pitch, positions, curves, sampling):
            i = observations.frame_index
            self.reinit_calls.append(i)
            return ReinitResult(corner if 4 <= i < 8 else reinit_camera(i), None, "lines")

    script = TwoCameras()
    run = run_of(tmp_path, FakeSolver(), script)
    cuts = {0: 0, 4: 1, 8: 2}
    shot = 0
    for i in range(11):
        shot = cuts.get(i, shot)
        f = frame(i)
        f.shot = FrameShot(shot, i in cuts, "main", "")
        run.process(f)
    result = run.finish()
    records = read_track(tmp_path / "run").records
    assert [r.camera_id for r in records] == ["main"] * 4 + ["high-corner-1"] * 4 + ["main"] * 3
    assert run.shot_camera_ids == {0: "main", 1: "high-corner-1", 2: "main"}
    camera_file = json.loads((tmp_path / "run" / "cameras" / "camera_000005.json").read_text())  # re-initialised
    assert camera_file["camera_id"] == "high-corner-1" and camera_file["position_meters"] == [53.0, 70.0, -22.0]
    assert result.summary["cuts"] == 2


def test_a_trusted_chain_s_camera_under_the_threshold_is_tried_after_growing_waits(tmp_path):
    # Frames 1-20 are solved at 0.4: under the threshold, over the lost confidence, in a trusted chain. The
    # re-initialisation finds nothing better (0.3), so the held camera stays and the next try waits 1, 2, 4, 8 frames.
    # A tripod holds the focal point (without one, a chain under 0.6 on most frames writes none of them: rule 7).
    solver = FakeSolver(held_tripod=HELD_TRIPOD)
    low = {i: 0.4 for i in range(1, 21)}
    script = Scripted(confidence=low, reinit_confidence={i: 0.3 for i in range(1, 21)})
    run = run_of(tmp_path, solver, script)
    for i in range(21):
        run.process(frame(i))
    run.finish()
    tried = [i for i in script.reinit_calls if i > 0]
    assert sorted(set(tried)) == [1, 2, 4, 8, 16]
    records = read_track(tmp_path / "run").records
    # Every frame is written (the chain is trusted), as solved: no frame between tries is replaced or held back.
    assert all(r.camera is not None and r.status == "tracked" for r in records[1:])
    assert solver.replaced == []


class FaintFound:
    """A frame's markings found ahead (a FoundMarkings' part the loop reads): 20 points, 30 with the faint look."""

    def __init__(self, i: int, looked_of: "FaintFound | None" = None) -> None:
        self.i, self.faint_look_of, self.seconds = i, looked_of, 0.0
        self.faint = None if looked_of is not None else "offered"
        self.points_work_px = np.zeros((20 if looked_of is None else 30, 2))
        self.faint_points_added = 0 if looked_of is None else 10
        self.unnamed = Detections(W, H, marking_points_px=self.points_work_px, marking_mask=np.ones((9, 16), bool),
                                  info={"faint_look": looked_of is not None, "frame": i})


class FaintLookDetector:
    """Names found markings with the middle line (with a predicted camera); records the frames whose faint look it was
    asked for."""

    def __init__(self) -> None:
        self.looked = []

    def name(self, found, predicted=None):
        lines = dict(LINES) if predicted is not None else {}
        return Detections(W, H, lines_px=lines, marking_points_px=found.points_work_px,
                          marking_mask=found.unnamed.marking_mask, info=dict(found.unnamed.info))

    def with_faint_lines(self, found):
        self.looked.append(found.i)
        return FaintFound(found.i, found)


@pytest.mark.parametrize("standard_placed, without_look, looked", [
    (False, 0.3, [0, 1, 2, 3]), (False, 0.9, [0]), (True, 0.9, [])])
def test_the_court_model_looks_again_with_the_faint_look_and_the_chain_keeps_it_only_when_needed(
        tmp_path, monkeypatch, standard_placed, without_look, looked):
    """The lost first frame's court camera: on the markings as found when ``standard_placed``, else only on their
    faint look (0.9 confident there) and ``without_look`` on those found without it: under the bar, the chain's frames
    keep the look. The global search finds nothing."""
    from broadtrack_graph.track import frame_loop

    def court(detections, frame_size, curves):
        if detections.info.get("faint_look") or standard_placed:
            return ReinitResult(reinit_camera(0), None, "court", tried=1)
        return ReinitResult(None, None, "", "nothing", tried=1)

    monkeypatch.setattr(frame_loop, "court_reinit", court)
    detector = FaintLookDetector()
    script = Scripted(fail={0})
    confidence = lambda camera, observations, detections, curves, sampling: (  # noqa: E731
        0.9 if detections.info.get("faint_look") or standard_placed else without_look)
    run = TrackingRun(W, H, tmp_path / "run", RunContext(TrackingConfig(use_flow=False), detector,
                                                         solver_factory=lambda *args: FakeSolver(),
                                                         reinitialise=script.reinitialise, confidence=confidence))
    for i in range(4):
        run.process(FrameInput(i, f"{i + 1:06d}", i / 25.0, image=np.full((4, 4, 3), i, np.uint8),
                               markings=FaintFound(i)))
    assert run.chain.faint_look == (without_look < 0.6)
    assert run.policy.counts["court_faint_look_used"] == (0 if standard_placed else 1)
    summary = run.finish().summary
    assert detector.looked == looked and summary["faint_look_frames"] == len(looked)
    assert script.reinit_calls == []  # the court model placed the frame: no search
    assert [(r.frame_index, r.status) for r in read_track(tmp_path / "run").records] == [
        (0, "reinitialised"), (1, "tracked"), (2, "tracked"), (3, "tracked")]


def test_frames_read_as_another_view_are_looked_at_by_the_court_model_alone_and_on_its_schedule(tmp_path,
                                                                                                monkeypatch):
    """A shot read as a close-up: its markings place a camera from frame 3 on (the court model's, at its bar; not on
    its second look's markings, which it does not take there), tracked from there; the refined guesses, the field
    model and the search never look at it. With none placed, every frame gets no camera and the court model looks
    at the shot's first frames, then more and more rarely."""
    from broadtrack_graph.shots.segmenter import FrameShot
    from broadtrack_graph.track import frame_loop

    for placed_from, on_look, frames in ((3, False, 6), (3, True, 6), (None, False, 40)):
        looked = []

        def court(detections, frame_size, curves):
            i, faint = detections.info["frame"], detections.info["faint_look"]
            looked.append((i, faint))
            if placed_from is not None and i >= placed_from and faint == on_look:
                return ReinitResult(reinit_camera(0), None, "court", tried=1)
            return ReinitResult(None, None, "", "no plausible camera")  # no hypothesis formed: a try all the same

        monkeypatch.setattr(frame_loop, "court_reinit", court)
        script = Scripted()
        folder = tmp_path / f"run{frames}{on_look}"
        run = TrackingRun(W, H, folder, RunContext(TrackingConfig(use_flow=False), FaintLookDetector(),
                                                   solver_factory=lambda *args: FakeSolver(),
                                                   reinitialise=script.reinitialise,
                                                   confidence=lambda *args: 0.9))
        for i in range(frames):
            run.process(FrameInput(i, f"{i + 1:06d}", i / 25.0, image=np.full((4, 4, 3), i, np.uint8),
                                   markings=FaintFound(i), shot=FrameShot(0, i == 0, "close-up", "big blob")))
        run.finish()
        records = read_track(folder).records
        assert script.reinit_calls == []  # no search on a frame read as another view
        assert not any(faint for _, faint in looked)  # no second look at a frame read as another view
        tried = [i for i, _ in looked]
        if placed_from is not None and not on_look:
            assert [r.status for r in records] == ["other-view"] * 3 + ["reinitialised", "tracked", "tracked"]
            assert records[0].reason.startswith("other view (close-up): big blob; court model: no camera")
            assert tried == [0, 1, 2, 3] and run.policy.counts["court_other_view_used"] == 1
            assert run.shot_camera_ids == {0: run.chain.camera_id} and run.chain.camera_id is not None
        elif on_look:
            assert all(r.status == "other-view" for r in records) and tried == list(range(6))
        else:
            assert all(r.status == "other-view" and r.camera is None for r in records)
            assert tried == list(range(11)) + [11, 13, 17, 25, 33]  # then waits of 1, 2, 4, 8, 8 frames
