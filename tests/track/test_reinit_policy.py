"""Cheap guesses before the global search (broadtrack_graph.track.reinit_policy), with fakes."""

from __future__ import annotations

import numpy as np

from broadtrack_graph.detect.observations import FrameObservations
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.reinit.scoring import LabelledScore, ReinitResult
from broadtrack_graph.track.reinit_policy import CheapFirstConfig, CheapFirstReinit

W, H = 1280, 720
GLOBAL_CAMERA = Camera(1500.0, 0.0, 0.2, 1.3, 0.0, (0.0, 55.0, -12.0), W, H)


def _result(camera, confidence):
    return ReinitResult(camera, LabelledScore(confidence, 0, 0, 0, 0.0, 0.0), "fake")


class Fakes:
    """A global search returning GLOBAL_CAMERA (or nothing) and a refiner echoing its first guess."""

    def __init__(self, cheap_confidence=0.8, global_confidence=0.6, global_finds=True):
        self.cheap_confidence, self.global_confidence, self.global_finds = cheap_confidence, global_confidence, global_finds
        self.global_calls, self.refined = [], []

    def global_search(self, observations, detections, pitch, positions, curves, sampling):
        self.global_calls.append(observations.frame_index)
        if not self.global_finds:
            return ReinitResult(None, None, "", "nothing found")
        return _result(GLOBAL_CAMERA, self.global_confidence)

    def refine(self, guesses, detections, curves):
        self.refined.append([label for label, _ in guesses])
        return _result(guesses[0][1], self.cheap_confidence)


def _frame(i):
    return FrameObservations(i, W, H)


def _confident_camera(pan=0.0):
    return Camera(1500.0, 0.0, pan, 1.3, 0.0, (1.0, 58.0, -15.0), W, H)


def test_without_a_confident_camera_the_global_search_runs():
    fakes = Fakes()
    policy = CheapFirstReinit(fakes.global_search, fakes.refine)
    result = policy(_frame(3), None, None)
    assert result.camera is GLOBAL_CAMERA and fakes.global_calls == [3] and fakes.refined == []


def test_a_confident_guess_skips_the_global_search():
    fakes = Fakes(cheap_confidence=0.7)
    policy = CheapFirstReinit(fakes.global_search, fakes.refine)
    seen = _confident_camera(0.1)
    policy.confident(10, seen)
    result = policy(_frame(12), None, None)
    assert result.camera is seen and fakes.global_calls == []
    assert fakes.refined == [["last confident camera (frame 10)"]]
    assert (policy.cheap_successes, policy.global_searches) == (1, 0)


def test_an_unconfident_guess_falls_back_to_the_global_search_and_the_better_one_wins():
    fakes = Fakes(cheap_confidence=0.4, global_confidence=0.6)
    policy = CheapFirstReinit(fakes.global_search, fakes.refine)
    policy.confident(10, _confident_camera())
    assert policy(_frame(11), None, None).camera is GLOBAL_CAMERA and fakes.global_calls == [11]
    fakes.global_confidence = 0.3  # the global search does worse than the guess: the guess is kept
    assert policy(_frame(12), None, None).camera is not GLOBAL_CAMERA
    fakes.global_finds = False  # the global search finds nothing: the guess is kept
    assert policy(_frame(13), None, None).camera is not None


def test_guesses_belong_to_their_camera_id_and_expire():
    fakes = Fakes()
    policy = CheapFirstReinit(fakes.global_search, fakes.refine, CheapFirstConfig(max_guess_age_frames=100))
    policy.switch("main")
    main = _confident_camera(0.3)
    policy.confident(5, main)
    policy.switch("high behind")  # another camera after a cut: the main camera is no guess for it
    assert policy.guesses(20, None) == []
    assert policy(_frame(20), None, None).camera is GLOBAL_CAMERA
    policy.switch("main")  # back to the main camera: its last confident camera first
    assert policy(_frame(40), None, None).camera is main
    assert policy.guesses(106, None) == []  # older than max_guess_age_frames


def test_a_known_tripod_adds_the_guess_moved_to_its_focal_point():
    policy = CheapFirstReinit(Fakes().global_search, Fakes().refine)
    seen = _confident_camera()
    policy.confident(0, seen)
    guesses = policy.guesses(1, [(0.0, 55.0, -12.0)])
    assert [label for label, _ in guesses] == ["last confident camera (frame 0)",
                                              "last confident camera (frame 0) at the tripod"]
    np.testing.assert_allclose(guesses[1][1].position_m, (0.0, 55.0, -12.0))
    assert guesses[1][1].pan_rad == seen.pan_rad
    assert len(policy.guesses(1, [tuple(seen.position_m)])) == 1  # already at the tripod: one guess
    off = CheapFirstReinit(Fakes().global_search, Fakes().refine, CheapFirstConfig(enabled=False))
    off.confident(0, seen)
    assert off.guesses(1, None) == []


def test_an_unconfident_search_at_the_tripod_is_followed_by_one_at_the_default_positions():
    calls = []

    def global_search(observations, detections, pitch, positions, curves, sampling):
        calls.append(positions)
        camera = GLOBAL_CAMERA if positions is None else GLOBAL_CAMERA.replace(focal_px=900.0)
        return _result(camera, 0.7 if positions is None else 0.3)

    policy = CheapFirstReinit(global_search, Fakes().refine)
    assert policy(_frame(1), None, None, [(0.0, 60.0, -15.0)]).camera is GLOBAL_CAMERA
    assert calls == [[(0.0, 60.0, -15.0)], None] and policy.global_searches == 2


def test_on_a_held_track_the_global_search_runs_at_most_once_per_gap():
    fakes = Fakes(cheap_confidence=0.4)
    policy = CheapFirstReinit(fakes.global_search, fakes.refine, CheapFirstConfig(tracking_gap_frames=5))
    policy.confident(0, _confident_camera())
    for i in range(1, 13):
        policy(_frame(i), None, None, tracking=True)
    assert fakes.global_calls == [1, 6, 11] and policy.skipped_searches == 9
    # A skipped frame gets the refined guess (the caller keeps whichever scores better).
    assert policy(_frame(12), None, None, tracking=True).camera is not GLOBAL_CAMERA
    # A lost frame (no camera held) always gets the global search.
    policy(_frame(13), None, None)
    assert fakes.global_calls[-1] == 13


def test_an_unconfident_search_result_replaces_the_refined_guess_only_when_clearly_better():
    fakes = Fakes(cheap_confidence=0.42, global_confidence=0.48)
    policy = CheapFirstReinit(fakes.global_search, fakes.refine)
    policy.confident(0, _confident_camera())
    assert policy(_frame(1), None, None).camera is not GLOBAL_CAMERA and policy.last_from_guess
    fakes.cheap_confidence = 0.3  # 0.48 is more than guess_margin (0.1) better: the search's camera
    assert policy(_frame(2), None, None).camera is GLOBAL_CAMERA and not policy.last_from_guess
