"""The one re-initialisation decision (broadtrack_graph.track.reinit_policy), with fakes."""

from __future__ import annotations

from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import pytest
from reinit_helpers import median_template_error_px

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.reinit.scoring import LabelledScore, ReinitResult
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.reinit_policy import ReinitPolicy
from broadtrack_graph.track.search_budget import SearchBudget
from broadtrack_graph.types.observations import FrameObservations

W, H = 1280, 720
MAIN = Camera(1500.0, 0.0, 0.2, 1.3, 0.0, (0.0, 55.0, -12.0), W, H)
CORNER = Camera(4400.0, 0.0, -0.1, 1.25, 0.0, (53.0, 70.0, -22.0), W, H)


class Fakes:
    """A staged search answering from a table, a refiner echoing its guess, and a confidence from a table.

    stage_answers: positions (None = defaults) -> (camera, confidence), or missing: nothing found.
    """

    def __init__(self, stage_answers=None, guess_confidence=0.8):
        self.stage_answers = stage_answers or {}
        self.guess_confidence = guess_confidence
        self.searched, self.refined = [], []
        self.confidences: dict[int, float] = {}

    def search(self, observations, detections, pitch, positions, curves, sampling):
        key = None if positions is None else tuple(map(tuple, positions))
        self.searched.append(key)
        answer = self.stage_answers.get(key)
        if answer is None:
            return ReinitResult(None, None, "", "nothing found")
        camera, confidence = answer
        self.confidences[id(camera)] = confidence
        return ReinitResult(camera, LabelledScore(0.99, 0, 0, 0, 0.0, 0.0), "fake search")

    def refine(self, guesses, detections, curves, hold_position=False):
        self.refined.append(guesses[0][0])
        self.held = hold_position
        return ReinitResult(guesses[0][1], LabelledScore(self.guess_confidence, 0, 0, 0, 0.0, 0.0), "fake fit")

    def confidence(self, camera, observations, detections, curves, sampling):
        return self.confidences.get(id(camera), 0.0)


def _policy(fakes, **config):
    """A policy on the fakes."""
    return ReinitPolicy(TrackingConfig(**config), fakes.search, fakes.refine, fakes.confidence)


WITH_MAP = SimpleNamespace(marking_mask=np.ones((9, 16), bool))  # detections with a marking map: the costly search


def _decide(policy, i, detections=WITH_MAP, chain_trusted=False, **kw):
    if chain_trusted:
        policy.chain.trust(i)  # (the chain's trust, as the judge gives it)
    return policy.decide(FrameObservations(i, W, H), detections, None, None, None, **kw)


def _cut(policy):
    """A cut, as the frame loop tells it: the chain's camera is unknown, and the policy's stretch starts over."""
    policy.chain.new_stretch()
    policy.new_stretch()


def test_a_new_shot_is_searched_at_the_known_cameras_and_the_default_positions_only():
    elsewhere = ((52.5, 70.0, -22.0),)  # a place cameras stand at, not searched
    fakes = Fakes({None: (MAIN, 0.3), elsewhere: (CORNER, 0.95)})
    decision = _decide(_policy(fakes), 0)
    assert decision.camera is MAIN and fakes.searched == [None]
    known = (53.0, 70.0, -22.0)
    fakes = Fakes({(known,): (CORNER, 0.55)})  # confident, not by the margin: the default stage follows, no other
    policy = _policy(fakes)
    policy.tripod("high-corner-1", known)
    decision = _decide(policy, 0)
    assert decision.camera is CORNER and decision.camera_id == "high-corner-1" and fakes.searched == [(known,), None]
    # The better of the two stages' cameras wins.
    fakes = Fakes({(known,): (CORNER, 0.5), None: (MAIN, 0.62)})
    policy = _policy(fakes)
    policy.tripod("high-corner-1", known)
    assert _decide(policy, 0).camera is MAIN
    # Mid-shot, a known camera that is not a main camera: its own position alone, on a marking map or labelled
    # detections.
    for detections in (WITH_MAP, None):
        fakes = Fakes()
        policy = _policy(fakes)
        policy.chain.identify("high-corner-1")
        policy.tripod("high-corner-1", known)
        _decide(policy, 5, detections=detections)
        assert fakes.searched == [(known,)]


def test_without_the_global_search_a_marking_map_is_not_searched():
    fakes = Fakes({None: (MAIN, 0.95), ((0.0, 55.0, -12.0),): (MAIN, 0.9)}, guess_confidence=0.1)
    policy = _policy(fakes, global_search=False)
    decision = _decide(policy, 0)
    assert decision.camera is None and not decision.searched and fakes.searched == []
    policy.chain.identify("main")
    policy.tripod("main", (0.0, 55.0, -12.0))
    assert not _decide(policy, 5).searched and fakes.searched == []
    assert _decide(policy, 6, detections=None).searched  # labelled detections: the search is their only route


def test_mid_shot_the_first_confident_stage_ends_the_search():
    fakes = Fakes({((0.0, 55.0, -12.0),): (MAIN, 0.3), None: (MAIN, 0.6)})
    policy = _policy(fakes)
    policy.chain.identify("main")
    policy.tripod("main", (0.0, 55.0, -12.0))
    decision = _decide(policy, 5)
    assert decision.camera is MAIN and decision.camera_id == "main"
    assert fakes.searched == [((0.0, 55.0, -12.0),), None]  # the camera's position, then its kind's stage


def test_a_certain_default_camera_stops_the_search_and_is_the_main_camera():
    fakes = Fakes({None: (MAIN, 0.95)})
    decision = _decide(_policy(fakes), 0)
    assert decision.camera is MAIN and decision.camera_id == "main" and fakes.searched == [None]


def test_a_confident_guess_skips_the_search_and_continues_the_chain():
    fakes = Fakes({None: (MAIN, 0.9)}, guess_confidence=0.7)
    policy = _policy(fakes)
    policy.chain.identify("main")
    policy.confident(10, MAIN)
    decision = _decide(policy, 12)
    assert decision.camera is MAIN and decision.continues_chain and decision.camera_id == "main"
    assert fakes.searched == [] and fakes.refined == ["last confident camera of main (frame 10)"]


def test_a_returning_camera_is_recognised_by_its_guess_after_a_cut():
    fakes = Fakes(guess_confidence=0.75)
    policy = _policy(fakes)
    policy.chain.identify("high-corner-1")
    policy.confident(5, CORNER)
    policy.chain.identify("main")
    policy.confident(50, MAIN)
    _cut(policy)  # a cut: the camera is unknown, every known camera is guessed
    decision = _decide(policy, 60)
    assert decision.camera_id in ("main", "high-corner-1") and decision.continues_chain
    assert set(fakes.refined) == {"last confident camera of high-corner-1 (frame 5)",
                                  "last confident camera of main (frame 50)"}


def test_a_shot_no_known_camera_explains_tries_their_guesses_on_its_first_frames_then_after_growing_gaps():
    fakes = Fakes(guess_confidence=0.2)  # the known cameras' guesses explain little: another camera's shot
    policy = _policy(fakes)
    for camera_id, camera, frame in (("high-corner-1", CORNER, 5), ("main", MAIN, 50)):
        policy.chain.identify(camera_id)
        policy.confident(frame, camera)
    _cut(policy)
    tried = []
    for i in range(100, 140):
        before = len(fakes.refined)
        _decide(policy, i)
        tried += [i - 100] if len(fakes.refined) > before else []
    assert tried == list(range(11)) + [11, 13, 17, 25, 33]  # two refinements each, then 1, 2, 4, 8 frames apart
    assert len(fakes.refined) == 2 * len(tried)
    # The shot's own camera, once known, is guessed on every frame (its chain's continuation).
    policy.chain.identify("main")
    before = len(fakes.refined)
    for i in range(140, 145):
        _decide(policy, i)
    assert fakes.refined[before:] == ["last confident camera of main (frame 50)"] * 5


def test_a_trusted_chain_s_held_camera_stays_unless_the_new_one_is_better_by_the_margin():
    fakes = Fakes({None: (MAIN, 0.45)})
    held = MAIN.replace(pan_rad=0.3)
    untrusted = _decide(_policy(fakes), 0, held=held, held_confidence=0.40, chain_trusted=False)
    assert untrusted.camera is MAIN  # a chain not trusted yet takes any better camera
    # On a marking map a trusted chain's held camera is refined (the fake refiner echoes it at guess_confidence),
    # not searched for; the refined camera replaces it only by the margin.
    fakes = Fakes({None: (MAIN, 0.9)}, guess_confidence=0.45)
    kept = _decide(_policy(fakes), 0, held=held, held_confidence=0.40, chain_trusted=True)
    assert kept.camera is None and "kept the held camera" in kept.reason
    assert fakes.searched == [] and fakes.refined == ["the held camera"]
    fakes = Fakes(guess_confidence=0.55)  # confident, but not the margin better than the held 0.48
    assert _decide(_policy(fakes), 0, held=held, held_confidence=0.48, chain_trusted=True).camera is None
    fakes = Fakes(guess_confidence=0.59)
    assert _decide(_policy(fakes), 0, held=held, held_confidence=0.48, chain_trusted=True).camera is held
    # Labelled detections (no map, nothing to refine on): the search decides, by the same margin.
    fakes = Fakes({None: (MAIN, 0.55)})
    assert _decide(_policy(fakes), 0, None, held=held, held_confidence=0.48, chain_trusted=True).camera is None
    fakes = Fakes({None: (MAIN, 0.59)})
    assert _decide(_policy(fakes), 0, None, held=held, held_confidence=0.48, chain_trusted=True).camera is MAIN


def test_the_budget_spaces_failed_searches_and_a_cut_restarts_it():
    fakes = Fakes()  # nothing is ever found
    policy = _policy(fakes, search_cost_frames=5.0, search_time_share=0.2, max_search_backoff=8)
    first = _decide(policy, 0)
    assert first.camera is None and first.searched and fakes.searched == [None]  # no known camera: one stage
    blocked = _decide(policy, 1)
    assert not blocked.searched and "next global search at frame" in blocked.reason
    # The shot's own search leaves the bucket empty; a frame refills 1/20 of a stage and, after a failure, the next
    # stage costs 2: searched again at frame 40.
    assert policy.searches.budget.next_frame(1) == 40
    searched = [i for i in range(1, 700) if _decide(policy, i).searched]
    # Each retry (one stage) doubles the price, up to 8: gaps of 80, 160, then 160 frames.
    assert searched == [40, 120, 280, 440, 600]
    assert fakes.searched[1:] == [None] * 5
    _cut(policy)
    assert _decide(policy, 700).searched and len(fakes.searched) == 7  # a new shot: searched at once


def test_search_budget_in_frames():
    budget = SearchBudget(refill_frames=10.0, max_backoff=4)
    assert budget.allows(0)
    budget.spend(0, found=False)  # price doubles: the next needs 2 searches' worth
    assert not budget.allows(10) and budget.next_frame(10) == 20 and budget.allows(20)
    budget.spend(20, found=False, searches=2)
    assert budget.price == 4 and budget.next_frame(20) == 20 + (4 + 2) * 10
    budget.restart()
    assert budget.allows(21) and budget.price == 1


def test_a_known_camera_lost_mid_shot_is_searched_again_after_growing_gaps():
    budget = SearchBudget(refill_frames=10.0, max_backoff=2, max_gap_frames=4)
    searched = []
    for i in range(40):
        if budget.allows(i, known_camera=True):
            searched.append(i)
            budget.spend(i, found=False, known_camera=True)
    assert searched == [0, 1, 3, 7, 15, 23, 31, 39]  # gaps 1, 2, 4, 8, then at most 4 * 2
    budget.spend(39, found=True, known_camera=True)
    assert budget.allows(40, known_camera=True)


def test_given_positions_replace_the_stages():
    position = (10.0, 60.0, -15.0)
    fakes = Fakes({(position,): (MAIN, 0.6)})
    policy = ReinitPolicy(TrackingConfig(), fakes.search, fakes.refine, fakes.confidence, search_positions=[position])
    assert _decide(policy, 0).camera is MAIN and fakes.searched == [(position,)]


def test_known_cameras_are_searched_first():
    fakes = Fakes({((53.0, 70.0, -22.0),): (CORNER, 0.6)})  # confident at a known camera's position: returning
    policy = _policy(fakes)
    policy.tripod("high-corner-1", (53.0, 70.0, -22.0))
    decision = _decide(policy, 0)
    assert decision.camera is CORNER and decision.camera_id == "high-corner-1" and len(fakes.searched) == 1


def test_without_a_marking_map_one_cheap_search_and_no_budget():
    fakes = Fakes()  # keypoints or labelled lines: searched at once, every frame
    policy = _policy(fakes)
    for i in range(3):
        assert _decide(policy, i, detections=None).searched
    assert fakes.searched == [None, None, None] and policy.counts["skipped_by_budget"] == 0


def test_no_guesses_without_cheap_reinit():
    fakes = Fakes({None: (MAIN, 0.6)})
    policy = _policy(fakes, cheap_reinit=False)
    policy.chain.identify("main")
    policy.confident(0, MAIN)
    assert _decide(policy, 1).searched and fakes.refined == []


def test_tracking_config_rejects_a_bad_budget():
    with pytest.raises(ValueError, match="search_time_share"):
        TrackingConfig(search_time_share=0.0)
    with pytest.raises(ValueError, match="max_search_backoff"):
        replace(TrackingConfig(), max_search_backoff=0)


def test_at_a_shot_start_a_guess_that_moved_to_another_camera_is_not_that_camera():
    fakes = Fakes({None: (MAIN, 0.3)}, guess_confidence=0.75)
    lower = MAIN.replace(position_m=np.array([0.0, 55.0, -6.0]))  # 6 m lower: across the line of sight
    fakes.refine = lambda guesses, detections, curves: ReinitResult(
        lower, LabelledScore(0.75, 0, 0, 0, 0.0, 0.0), "fake fit")
    policy = _policy(fakes)
    policy.chain.identify("main")
    policy.confident(50, MAIN)
    policy.tripod("main", (0.0, 55.0, -12.0))
    _cut(policy)
    decision = _decide(policy, 60)
    assert decision.camera is not lower and fakes.searched  # the guess is dropped, the stages are searched
    # Mid-shot the shot's own camera may move (its first lock was off): the guess stands.
    policy = _policy(fakes)
    policy.chain.identify("main")
    policy.confident(50, MAIN)
    decision = _decide(policy, 52)
    assert decision.camera is lower and decision.camera_id == "main" and decision.continues_chain


def test_a_returning_camera_ends_the_search_only_when_confident_by_the_margin():
    known = ((53.0, 70.0, -22.0),)
    fakes = Fakes({known: (CORNER, 0.55)})  # confident, but not by the margin: the default stage is searched
    policy = _policy(fakes)
    policy.tripod("high-corner-1", known[0])
    decision = _decide(policy, 0)
    assert decision.camera is CORNER and fakes.searched == [known, None]


def test_a_camera_found_at_a_known_position_that_stands_elsewhere_is_a_new_camera_searched_in_full():
    known = ((53.0, 70.0, -22.0),)
    elsewhere = CORNER.replace(position_m=(40.0, 70.0, -22.0))  # 13 m across its line of sight from the known one
    fakes = Fakes({known: (elsewhere, 0.7)})
    policy = _policy(fakes)
    policy.tripod("high-corner-1", known[0])
    decision = _decide(policy, 0)
    assert decision.camera is elsewhere and fakes.searched == [known, None]
    assert decision.camera_id not in (None, "high-corner-1")


def test_a_new_camera_s_id_is_provisional_until_its_chain_is_trusted():
    # 0.55: above the threshold, under a new shot's trust (0.6). Its id is provisional: while its chain has had no
    # trusted frame, a camera searched for the shot is judged as a new shot's, and a cut forgets the id (a wrong
    # first camera does not become a known camera whose searches are judged at the threshold, mid-shot).
    fakes = Fakes({None: (MAIN, 0.55), ((0.0, 55.0, -12.0),): (MAIN, 0.55)})
    policy = _policy(fakes, search_time_share=1.0)
    decision = _decide(policy, 0)
    assert decision.camera is MAIN and decision.camera_id == "main" and decision.new_camera
    assert policy.registry.untrusted == {"main"}
    policy.chain.identify("main")  # (as the frame loop does on adopting the decision)
    fakes.searched.clear()
    decision = _decide(policy, 1)
    assert fakes.searched[0] == ((0.0, 55.0, -12.0),)  # searched about where it stands, as mid-shot ...
    assert decision.camera_id == "main" and decision.new_camera  # ... and judged as a new shot's camera
    _cut(policy)  # a cut: the id of a camera never trusted is forgotten
    assert policy.registry.positions == {} and policy.registry.untrusted == set()
    # Trusted once (a confident frame), the id is kept across cuts and judged as a known camera's mid-shot.
    fakes = Fakes({None: (MAIN, 0.55), ((0.0, 55.0, -12.0),): (MAIN, 0.55)}, guess_confidence=0.3)
    policy = _policy(fakes, search_time_share=1.0)
    _decide(policy, 0)
    policy.chain.identify("main")
    policy.chain.trust(3)  # (as the frame loop does on a trusted, confident frame)
    policy.confident(3, MAIN)
    decision = _decide(policy, 4)  # its guess is not confident: searched
    assert decision.searched and decision.camera_id == "main" and not decision.new_camera
    _cut(policy)
    assert set(policy.registry.positions) == {"main"} and policy.registry.untrusted == set()


def test_a_provisional_camera_s_searches_back_off_until_one_is_trusted():
    # Each search about a provisional camera finds it again at 0.55 (above the threshold, under a new shot's trust):
    # that is not a trusted camera, so the searches back off (1, 2, 4, ... frames) instead of running every frame.
    fakes = Fakes({None: (MAIN, 0.55), ((0.0, 55.0, -12.0),): (MAIN, 0.55)}, guess_confidence=0.3)
    policy = _policy(fakes)
    _decide(policy, 0)
    policy.chain.identify("main")
    searched = [i for i in range(1, 40) if _decide(policy, i).searched]
    assert searched == [1, 2, 4, 8, 16, 32]
    # A search that gives a camera trusted from its frame (0.6, a new shot's trust) restarts the gaps.
    fakes.stage_answers[((0.0, 55.0, -12.0),)] = (MAIN, 0.65)
    assert _decide(policy, 64).searched and _decide(policy, 65).searched


class FakeModel:
    """The field model's camera: a fixed camera (or None) whose confidence the fakes' table gives."""

    def __init__(self, fakes, camera, confidence):
        self.camera, self.calls = camera, []
        if camera is not None:
            fakes.confidences[id(camera)] = confidence

    def __call__(self, image):
        self.calls.append(image)
        if self.camera is None:
            return ReinitResult(None, None, "", "field model: 0 keypoints")
        return ReinitResult(self.camera, LabelledScore(0.0, 12, 0, 0, 1.0, 1.0), "field model (12 keypoints)")


IMAGE = np.zeros((H, W, 3), np.uint8)


def _with_model(fakes, camera, confidence, **config):
    model = FakeModel(fakes, camera, confidence)
    return ReinitPolicy(TrackingConfig(**config), fakes.search, fakes.refine, fakes.confidence, model=model), model


def test_a_confident_model_camera_skips_the_search_and_gets_the_camera_id_of_where_it_stands():
    fakes = Fakes({None: (MAIN, 0.9)})
    policy, model = _with_model(fakes, CORNER, 0.92)
    decision = _decide(policy, 0, image=IMAGE)
    assert decision.camera is CORNER and decision.camera_id == "high-corner-1" and decision.new_camera
    assert not decision.searched and not decision.continues_chain and fakes.searched == []
    assert policy.counts["model_used"] == 1 and len(model.calls) == 1


def test_a_new_shot_takes_the_model_camera_at_once_only_when_certain():
    fakes = Fakes({None: (MAIN, 0.95)})
    policy, _ = _with_model(fakes, CORNER, 0.8)  # confident by the margin, not certain (0.9)
    decision = _decide(policy, 0, image=IMAGE)
    assert fakes.searched and decision.camera is MAIN  # the search ran and found a better camera
    fakes = Fakes()
    policy, _ = _with_model(fakes, CORNER, 0.8)
    decision = _decide(policy, 0, image=IMAGE)
    assert decision.camera is CORNER and decision.searched and decision.new_camera  # nothing better: the candidate


def test_mid_shot_a_model_camera_above_the_threshold_is_taken_for_the_shots_camera():
    fakes = Fakes({None: (MAIN, 0.9)})
    policy, _ = _with_model(fakes, MAIN, 0.55, cheap_reinit=False)
    policy.chain.identify("main")
    decision = _decide(policy, 3, image=IMAGE)
    assert decision.camera is MAIN and decision.camera_id == "main" and not decision.searched


def test_the_model_tries_a_shot_s_first_frames_one_by_one_then_backs_off_and_restarts_after_a_cut():
    fakes = Fakes()
    policy, model = _with_model(fakes, None, 0.0, search_time_share=1.0)

    def tried(frames):  # the frames the model tried
        out = []
        for i in frames:
            calls = len(model.calls)
            _decide(policy, i, image=IMAGE)
            if len(model.calls) > calls:
                out.append(i)
        return out

    # A shot's first 10 frames it cannot place, one by one; then gaps of 1, 2, 4, 8 (at most 8).
    assert tried(range(40)) == [*range(10), 10, 11, 13, 17, 25, 33]
    assert policy.counts["model_tried"] == 16
    policy.confident(40, MAIN)  # a loss after a confident frame: the gaps start again at 1, no run of tries
    assert tried(range(41, 50)) == [41, 42, 44, 48]
    _cut(policy)  # a cut: the new shot's first frames one by one again
    assert tried(range(50, 62)) == [*range(50, 60), 60, 61]


def test_no_image_no_model():
    fakes = Fakes({None: (MAIN, 0.9)})
    policy, model = _with_model(fakes, CORNER, 0.9)
    decision = _decide(policy, 0)
    assert model.calls == [] and decision.camera is MAIN


def test_a_model_camera_that_is_not_taken_registers_no_camera():
    fakes = Fakes({None: (MAIN, 0.85)})
    policy, _ = _with_model(fakes, CORNER, 0.8)  # a candidate only: the search runs and its camera wins
    decision = _decide(policy, 0, image=IMAGE)
    assert decision.camera is MAIN and set(policy.registry.positions) == {"main"}


def _a_new_shot_s_decision(image: np.ndarray, frame_index: int):
    """The real tracker's policy (weight-free detections, the court model, the staged search, no field model, one
    process) on a new shot's first frames, a still camera: the first decision with a camera (the court model's camera
    under its bar waits for the next frames' to agree)."""
    from broadtrack_graph.detect.weightfree import WeightFreeDetector
    from broadtrack_graph.geometry.pitch import PitchTemplate
    from broadtrack_graph.geometry.template import TemplateSampling, fitting_curves
    from broadtrack_graph.reinit.cheap import refine_guesses
    from broadtrack_graph.reinit.court import court_reinit
    from broadtrack_graph.reinit.frame import frame_confidence, reinitialise

    detections = WeightFreeDetector().detect(image, None)
    pitch = PitchTemplate()
    config = TrackingConfig()
    policy = ReinitPolicy(config, reinitialise, refine_guesses, frame_confidence, court=court_reinit)
    height, width = image.shape[:2]
    for index in range(frame_index, frame_index + config.court_agreement_frames + 1):
        decision = policy.decide(FrameObservations(index, width, height), detections, pitch, fitting_curves(pitch),
                                 TemplateSampling(pitch))
        if decision.camera is not None:
            break
    return decision


def test_a_main_camera_seeing_the_centre_spot_low_is_found_at_its_first_frames(real_video_dir, tmp_path):
    """The FA Cup clip's first frame cut to its middle 574 rows and written as MPEG-4 video, as a screen recording
    is: a centre-circle view whose boards' lettering passes for markings. Its camera sees the centre spot 9.3 deg
    below the horizon (12.4 deg for the main-camera guesses of the search). With a ridge point kept only where grass
    lies on both sides of it (detect.ridge_sides), the court model's camera is confident enough at once."""
    import cv2

    capture = cv2.VideoCapture(str(real_video_dir / "facup-wembley-720p.mp4"))
    ok, image = capture.read()
    capture.release()
    assert ok and image.shape[:2] == (720, 1280)
    recording = str(tmp_path / "crop.mp4")
    writer = cv2.VideoWriter(recording, cv2.VideoWriter_fourcc(*"mp4v"), 25.0, (1280, 574))
    writer.write(np.ascontiguousarray(image[73:647]))
    writer.release()
    ok, image = cv2.VideoCapture(recording).read()
    assert ok and image.shape[:2] == (574, 1280)
    decision = _a_new_shot_s_decision(image, 0)
    camera = decision.camera
    assert camera is not None and decision.confidence > 0.6 and decision.camera_id == "main", decision.reason
    assert decision.reason.startswith("court model"), decision.reason
    # The camera this clip is tracked with (every frame passes the alignment check of `bench real`); one frame
    # leaves the distance along the line of sight loose (f scales with it), the image is what must agree.
    tracked = Camera(4045.0, 0.56, np.radians(-7.29), np.radians(81.87), np.radians(-0.12), (0.19, 74.87, -12.43),
                     1280, 574)
    from broadtrack_graph.geometry.pitch import PitchTemplate

    pitch = PitchTemplate()
    ground = np.vstack([p for name, p in pitch.sample_uniform(1.0).items() if pitch.is_on_ground(name)])
    uv_tracked, front_tracked = tracked.project(ground)
    assert np.count_nonzero(front_tracked & tracked.in_image(uv_tracked)) > 100
    assert median_template_error_px(camera, tracked) < 4.0
    assert camera.position_m[0] == pytest.approx(0.0, abs=1.0) and camera.position_m[2] < -10.0


def test_a_main_camera_metres_from_every_candidate_position_is_found_at_its_first_frame(real_video_dir):
    """Frame 300 of the 360p clip: a wide view between the centre circle and the right penalty area, its camera
    4-5 m from every candidate focal point of the search (whose best fit, 0.55, is 77 px off): the court model
    places it."""
    import cv2

    capture = cv2.VideoCapture(str(real_video_dir / "jpn-tjk-360p-with-cut.mp4"))
    for _ in range(301):
        ok, image = capture.read()
    capture.release()
    assert ok and image.shape[:2] == (360, 640)
    decision = _a_new_shot_s_decision(image, 300)
    camera = decision.camera
    assert camera is not None and decision.confidence > 0.7, decision.reason
    assert decision.reason.startswith("court model"), decision.reason
    # The camera this frame is tracked with from the clip's start (every frame passes `bench real`'s check).
    tracked = Camera(774.8, 0.026, np.radians(22.54), np.radians(67.64), np.radians(0.29), (1.47, 59.57, -16.85),
                     640, 360)
    assert median_template_error_px(camera, tracked) < 3.0
    assert np.linalg.norm(camera.position_m - np.asarray(tracked.position_m)) < 1.5


# --------------------------------------------------------------------------- the court model


def _court_policy(fakes, court_camera, court_confidence, registry=None, explained=None, **config):
    """A policy whose court model answers court_camera (with its twin and the markings it ``explained``), scored
    court_confidence by the fakes."""
    from broadtrack_graph.reinit.court_fit import twin_camera
    from broadtrack_graph.track.camera_ids import CameraRegistry

    calls = []

    def court(detections, frame_size, curves):
        calls.append(frame_size)
        if court_camera is None:
            return ReinitResult(None, None, "", "nothing")
        fakes.confidences[id(court_camera)] = court_confidence
        twin = twin_camera(court_camera)
        fakes.confidences[id(twin)] = court_confidence
        return ReinitResult(court_camera, None, "fake court", twin=twin, explained=explained)

    policy = ReinitPolicy(TrackingConfig(**config), fakes.search, fakes.refine, fakes.confidence,
                          registry or CameraRegistry(), court=court)
    return policy, calls


def test_a_confident_court_camera_starts_a_new_shot_without_the_search():
    fakes = Fakes({None: (MAIN, 0.9)})
    policy, calls = _court_policy(fakes, CORNER, 0.75)
    decision = _decide(policy, 0)
    assert decision.camera is CORNER and decision.new_camera and not decision.searched
    assert fakes.searched == [] and calls == [(W, H)] and policy.counts["court_used"] == 1


OWN_POSITION = (tuple(MAIN.position_m),)  # the shot's known camera's position: its search stage


def _court_policy_mid_shot(fakes, court_camera, court_confidence, untrusted=False, **config):
    """:func:`_court_policy` on a shot whose camera is the known main camera (no guesses of it), lost: searched at its
    own position alone, never at the default positions (the court model looks wherever the camera stands);
    ``untrusted``: its id provisional (a new camera's, judged as a new shot's)."""
    policy, calls = _court_policy(fakes, court_camera, court_confidence, **config)
    policy.tripod("main", MAIN.position_m)
    if untrusted:
        policy.registry.untrusted.add("main")
    policy.chain.identify("main")
    return policy, calls


def test_an_unconfident_court_camera_is_dropped_and_known_cameras_are_searched_at_their_positions():
    fakes = Fakes({OWN_POSITION: (MAIN, 0.62), None: (CORNER, 0.95)})
    policy, _ = _court_policy_mid_shot(fakes, CORNER, 0.3)
    decision = _decide(policy, 5)
    assert decision.camera is MAIN and decision.searched and policy.counts["court_used"] == 0
    assert fakes.searched == [OWN_POSITION]  # the default positions are not searched where the court model looks
    # A new shot: the known cameras' positions alone, for a returning camera (never the default positions).
    fakes = Fakes({None: (MAIN, 0.95), OWN_POSITION: (MAIN, 0.95)}, guess_confidence=0.95)
    policy, _ = _court_policy(fakes, CORNER, 0.3)
    policy.tripod("main", MAIN.position_m)
    decision = _decide(policy, 0)
    assert decision.camera is MAIN and decision.searched and fakes.searched == [OWN_POSITION]
    assert decision.camera_id == "main"  # (no confident camera of it seen yet: no guess of it to refine)
    # ... and nothing else: a camera the known cameras' stage finds elsewhere, even certain, is the court model's to
    # place; with no known camera there is nothing to search.
    elsewhere = CORNER.replace(position_m=(20.0, 80.0, -15.0))
    fakes = Fakes({OWN_POSITION: (elsewhere, 0.99)}, guess_confidence=0.1)
    policy, _ = _court_policy(fakes, CORNER, 0.3)
    policy.tripod("main", MAIN.position_m)
    decision = _decide(policy, 0)
    assert decision.camera is None and decision.searched and fakes.searched == [OWN_POSITION]
    fakes = Fakes({None: (MAIN, 0.95)}, guess_confidence=0.1)
    policy, _ = _court_policy(fakes, CORNER, 0.3)
    decision = _decide(policy, 0)
    assert decision.camera is None and not decision.searched and fakes.searched == []
    assert decision.reason == "no search: the court model looks wherever the camera stands"


def _drawn_map(camera: Camera, pitch) -> np.ndarray:
    """The marking map of every ground marking as the camera draws it (its 0.1 m samples, 3 px wide)."""
    import cv2

    marks = np.zeros((camera.height_px, camera.width_px), np.uint8)
    for name, points in pitch.sample_uniform(0.1).items():
        uv, front = camera.project(points) if pitch.is_on_ground(name) else (np.zeros((0, 2)), np.zeros(0, bool))
        uv = np.rint(uv[front]).astype(int)
        inside = (uv[:, 0] >= 0) & (uv[:, 0] < camera.width_px) & (uv[:, 1] >= 0) & (uv[:, 1] < camera.height_px)
        marks[uv[inside, 1], uv[inside, 0]] = 1
    return cv2.dilate(marks, np.ones((3, 3), np.uint8)) > 0


def test_a_returning_camera_s_view_fixed_only_on_its_tripod_is_taken_there_and_nowhere_else():
    """A zoomed view of the main camera after a cut, the far touchline and a fifth of the centre circle: 5 constraints,
    a camera's 7 unknowns from nothing, 4 on a known tripod (its focal point known)."""
    from broadtrack_graph.geometry.aim import aim_angles
    from broadtrack_graph.geometry.pitch import PitchTemplate

    pitch = PitchTemplate()
    position = np.array([0.0, 55.0, -12.0])
    pan, tilt = aim_angles(position, np.array([10.0, -25.0, 0.0]))
    zoomed = Camera(640.0 / np.tan(np.radians(6.0)), 0.0, pan, tilt, 0.0, position, W, H)  # 12 deg across
    detections = SimpleNamespace(marking_mask=_drawn_map(zoomed, pitch))
    fakes = Fakes({(tuple(position),): (zoomed, 0.9)}, guess_confidence=0.9)
    policy, _ = _court_policy(fakes, None, 0.0)  # the court model places nothing
    policy.tripod("main", position)
    decision = policy.decide(FrameObservations(0, W, H), detections, pitch, None, None)
    assert decision.camera is zoomed and decision.camera_id == "main" and decision.searched
    # The same view as the court model's camera where no known camera stands: refused by the same gate.
    policy, _ = _court_policy(Fakes(), zoomed, 0.9)
    decision = policy.decide(FrameObservations(0, W, H), detections, pitch, None, None)
    assert decision.camera is None and "do not fix it" in decision.reason


def _zoomed_main(aim, hfov_deg: float, position=(0.0, 55.0, -12.0)) -> Camera:
    from broadtrack_graph.geometry.aim import aim_angles

    position = np.asarray(position, float)
    pan, tilt = aim_angles(position, np.asarray(aim, float))
    return Camera(640.0 / np.tan(np.radians(hfov_deg / 2)), 0.0, pan, tilt, 0.0, position, W, H)


def test_a_searched_camera_off_its_known_tripod_is_refitted_on_it_when_its_markings_fix_it_only_there():
    """The known camera's search frees the focal point near its position: a narrow view slides along its line of
    sight. Its markings (a touchline and a fifth of the centre circle) do not fix it from nothing; held on the tripod,
    its view kept, they do."""
    from broadtrack_graph.geometry.aim import moved_keeping_view
    from broadtrack_graph.geometry.pitch import PitchTemplate

    pitch = PitchTemplate()
    tripod = np.array([0.0, 55.0, -12.0])
    truth = _zoomed_main((10.0, -25.0, 0.0), 12.0)
    slid = moved_keeping_view(truth, tripod + 3.0 * truth.R_cw[2])  # 3 m down its line of sight
    detections = SimpleNamespace(marking_mask=_drawn_map(truth, pitch))
    fakes = Fakes({(tuple(tripod),): (slid, 0.9)}, guess_confidence=0.88)
    policy, _ = _court_policy(fakes, None, 0.0)
    policy.tripod("main", tripod)
    decision = policy.decide(FrameObservations(0, W, H), detections, pitch, None, None)
    assert decision.camera is not None and decision.camera_id == "main" and fakes.held
    np.testing.assert_allclose(decision.camera.position_m, tripod)
    assert abs(decision.camera.focal_px / truth.focal_px - 1.0) < 1e-9 and fakes.refined[-1] == "on the tripod of main"
    # Not explained there within the margin: the slid camera stays, and the gate refuses it.
    fakes = Fakes({(tuple(tripod),): (slid, 0.9)}, guess_confidence=0.9 - TrackingConfig().reinit_switch_margin - 0.01)
    policy, _ = _court_policy(fakes, None, 0.0)
    policy.tripod("main", tripod)
    assert policy.decide(FrameObservations(0, W, H), detections, pitch, None, None).camera is None


def _found_on_the_main_tripod(view: Camera, confidence: float):
    """The decision for a new shot whose known cameras' search finds ``view`` on the main camera's tripod at
    ``confidence`` (the court model placing nothing), its marking map drawn from ``view``."""
    from broadtrack_graph.geometry.pitch import PitchTemplate

    pitch = PitchTemplate()
    tripod = tuple(view.position_m)
    fakes = Fakes({(tripod,): (view, confidence)}, guess_confidence=0.9)
    policy, _ = _court_policy(fakes, None, 0.0)
    policy.tripod("main", tripod)
    return policy.decide(FrameObservations(0, W, H), SimpleNamespace(marking_mask=_drawn_map(view, pitch)), pitch,
                         None, None)


@pytest.mark.parametrize("confidence, taken", [(0.75, True), (0.65, False)])
def test_a_camera_its_markings_fix_only_on_its_tripod_is_taken_at_the_court_model_s_bar(confidence, taken):
    """A touchline and a fifth of the centre circle: fixed on a known tripod with a constraint to spare, taken there
    as sure as the court model's camera from nothing must be (0.7), not at the search's 0.6."""
    view = _zoomed_main((10.0, -25.0, 0.0), 12.0)
    assert (_found_on_the_main_tripod(view, confidence).camera is view) is taken
    assert (confidence >= TrackingConfig().court_accept_confidence) is taken


@pytest.mark.parametrize("confidence, taken", [(0.85, True), (0.75, False)])
def test_a_camera_its_markings_fix_exactly_on_its_tripod_is_taken_at_the_exact_fit_bar(confidence, taken):
    """One line of each direction (the far touchline and the halfway line, 8 deg across): 4 constraints, exactly the
    unknowns of a camera on a known tripod; taken from the court model's bar for exact fits."""
    from broadtrack_graph.track.known_tripod import EXACT_FIT_CONFIDENCE

    view = _zoomed_main((0.0, -30.0, 0.0), 8.0)
    assert (_found_on_the_main_tripod(view, confidence).camera is view) is taken
    assert (confidence >= EXACT_FIT_CONFIDENCE) is taken


def test_a_court_camera_under_its_bar_is_dropped_even_when_the_search_finds_less():
    config = TrackingConfig()
    fakes = Fakes({OWN_POSITION: (MAIN, config.confidence_threshold - 0.02)})
    unsure = config.confidence_threshold + config.reinit_switch_margin - 0.02  # not confident by the margin
    policy, _ = _court_policy_mid_shot(fakes, CORNER, unsure)
    decision = _decide(policy, 5)
    assert decision.camera is MAIN and decision.searched and policy.counts["court_used"] == 0
    policy, _ = _court_policy(Fakes(), CORNER, 0.8, court_accept_confidence=0.85)
    assert _decide(policy, 0).camera is None


def test_a_court_camera_explaining_a_grid_of_lines_is_taken_from_its_own_bar():
    from broadtrack_graph.geometry.determinable import Determinability

    config = TrackingConfig()
    between = (config.court_grid_accept_confidence + config.court_accept_confidence) / 2
    grid, one_across = Determinability(True, 2, 2, ()), Determinability(True, 1, 5, ("Circle right",))
    policy, _ = _court_policy(Fakes(), CORNER, between, explained=grid)
    decision = _decide(policy, 0)
    assert decision.camera is CORNER and decision.new_camera and policy.counts["court_used"] == 1
    policy, _ = _court_policy(Fakes(), CORNER, between, explained=one_across)
    assert _decide(policy, 0).camera is None  # waits for the next frames' court cameras
    # Never under the confidence a new camera's chain is trusted from.
    unsure = config.confidence_threshold + config.reinit_switch_margin - 0.02
    policy, _ = _court_policy(Fakes(), CORNER, unsure, explained=grid, court_grid_accept_confidence=0.5)
    assert _decide(policy, 0).camera is None and policy.counts["court_used"] == 0
    with pytest.raises(ValueError, match="court_grid_accept_confidence"):
        TrackingConfig(court_grid_accept_confidence=1.2)


def test_a_court_try_that_forms_no_hypothesis_does_not_make_the_court_model_wait():
    # Bare grass, then markings coming into view: frames that give the court model nothing to try (no hypothesis)
    # cost no wait, so it tries the first frame whose markings form hypotheses; frames whose hypotheses place
    # nothing make it back off (1, 2, 4, ... frames after its first tries).
    for tried, expected_calls in ((0, 30), (5, 11 + 4)):  # frames 0-10, then 11, 13, 17, 25
        policy, calls = _court_policy(Fakes(), None, 0.0)
        policy.tries.court = lambda detections, frame_size, curves, tried=tried: (
            calls.append(frame_size), ReinitResult(None, None, "", "nothing", tried=tried))[1]
        for i in range(30):
            _decide(policy, i)
        assert len(calls) == expected_calls, (tried, len(calls))


def test_a_provisional_camera_s_search_waits_for_the_next_frames_court_cameras():
    config = TrackingConfig()
    between = config.confidence_threshold + config.reinit_switch_margin + 0.02  # confident by the margin only
    fakes = Fakes({OWN_POSITION: (MAIN, 0.62)})
    policy, answers = _court_policy_mid_shot(fakes, CORNER, between, untrusted=True, court_agreement_frames=3)
    decision = _decide(policy, 0)
    assert decision.camera is None and not decision.searched and "waiting" in decision.reason
    assert fakes.searched == []
    policy.tries.court = lambda detections, frame_size, curves: ReinitResult(None, None, "", "nothing")
    assert _decide(policy, 1).camera is None and _decide(policy, 2).camera is None and fakes.searched == []
    decision = _decide(policy, 3)  # the window is over: the search is paid
    assert decision.searched and decision.camera is MAIN and fakes.searched == [OWN_POSITION]
    # A chain whose camera is known and trusted does not wait.
    fakes = Fakes({None: (MAIN, 0.62)})
    policy, _ = _court_policy(fakes, CORNER, between)
    policy.chain.identify("main")
    policy.registry.positions["main"] = MAIN.position_m
    assert _decide(policy, 0, chain_trusted=True).searched


def test_a_known_camera_standing_where_the_twin_stands_decides_the_twin():
    from broadtrack_graph.reinit.court_fit import twin_camera
    from broadtrack_graph.track.camera_ids import CameraRegistry

    far_side = twin_camera(MAIN)  # the court model's rule would keep the main side: here a known camera decides
    registry = CameraRegistry(known={"opposite": far_side.position_m})
    policy, _ = _court_policy(Fakes(), MAIN, 0.8, registry)
    decision = _decide(policy, 0)
    assert np.allclose(decision.camera.position_m, far_side.position_m) and decision.camera_id == "opposite"


def test_two_frames_whose_court_cameras_agree_place_the_camera_under_the_bar():
    config = TrackingConfig()
    between = config.confidence_threshold + config.reinit_switch_margin + 0.02  # confident by the margin only
    assert between < config.court_accept_confidence
    fakes = Fakes()
    panned = CORNER.replace(pan_rad=CORNER.pan_rad + 0.01)  # the same tripod, the view 44 px (3 %) along
    policy, _ = _court_policy(fakes, CORNER, between)
    assert _decide(policy, 0).camera is None  # one frame: under the bar
    policy.tries.court = _court_policy(fakes, panned, between)[0].tries.court
    assert _decide(policy, 1).camera is panned  # the next agrees from a view moved on: taken
    assert policy.counts["court_used"] == 1
    # A still camera: the next frame shows the same markings, and the same camera from them is no check.
    policy, _ = _court_policy(Fakes(), CORNER, between)
    assert _decide(policy, 0).camera is None and _decide(policy, 1).camera is None
    slightly = CORNER.replace(pan_rad=CORNER.pan_rad + 0.002)  # 9 px: under court_agreement_view_change
    policy, _ = _court_policy(fakes, CORNER, between)
    _decide(policy, 0)
    policy.tries.court = _court_policy(fakes, slightly, between)[0].tries.court
    assert _decide(policy, 1).camera is None
    fakes = Fakes()
    policy, _ = _court_policy(fakes, CORNER, between, court_agreement_frames=0)
    assert _decide(policy, 0).camera is None
    policy.tries.court = _court_policy(fakes, panned, between)[0].tries.court
    assert _decide(policy, 1).camera is None  # no agreement asked
    policy, _ = _court_policy(Fakes(), CORNER, between)
    _decide(policy, 0)
    _cut(policy)  # a cut between the two frames: no agreement across it
    policy.tries.court = _court_policy(fakes, panned, between)[0].tries.court
    assert _decide(policy, 1).camera is None


@pytest.mark.parametrize("at_tripod, camera_id", [(0.3, "main-1"), (0.9, "main")])
def test_a_new_shot_s_camera_takes_a_known_id_only_when_that_tripod_explains_the_frame(at_tripod, camera_id):
    from broadtrack_graph.track.camera_ids import CameraRegistry

    fakes = Fakes({None: (MAIN, 0.95)}, guess_confidence=at_tripod)  # the frame refined at the known tripod
    registry = CameraRegistry(known={"main": MAIN.position_m + np.array([0.0, 2.0, 0.0])})
    policy = ReinitPolicy(TrackingConfig(), fakes.search, fakes.refine, fakes.confidence,
                          registry)
    decision = _decide(policy, 0)
    assert decision.camera is MAIN and decision.camera_id == camera_id
    assert any("at the position of main" in label for label in fakes.refined)


def test_a_trusted_chain_s_held_camera_is_not_tried_by_the_calibrators_from_nothing():
    fakes = Fakes({None: (MAIN, 0.3)}, guess_confidence=0.5)
    policy, calls = _court_policy(fakes, CORNER, 0.95)
    policy.chain.identify("main")
    policy.registry.positions["main"] = MAIN.position_m
    held = MAIN.replace(pan_rad=0.3)
    decision = _decide(policy, 0, held=held, held_confidence=0.45, chain_trusted=True)
    assert calls == [] and policy.counts["court_tried"] == 0 and decision.camera is None and fakes.searched == []
    # Lost (no held camera), the court model is tried again.
    decision = _decide(policy, 1)
    assert calls == [(W, H)] and decision.camera is CORNER


def test_a_chain_s_first_camera_is_dropped_unless_the_markings_it_explains_fix_it():
    from broadtrack_graph.geometry.pitch import PitchTemplate

    pitch = PitchTemplate()

    def decided(marking_mask, **kw):
        fakes = Fakes({None: (MAIN, 0.95)})  # certain: the search ends at the default positions
        detections = SimpleNamespace(marking_mask=marking_mask)
        policy = _policy(fakes)
        return policy, policy.decide(FrameObservations(0, W, H), detections, pitch, None, None, **kw)

    _, kept = decided(np.ones((9, 16), bool))  # every marking MAIN shows is on the map
    assert kept.camera is MAIN
    _, dropped = decided(np.zeros((9, 16), bool))  # none is: nothing fixes the camera
    assert dropped.camera is None and dropped.reason.startswith("the markings the camera explains do not fix it")
    # A trusted chain's camera is the tracker's: not judged so.
    policy = _policy(Fakes({((0.0, 55.0, -12.0),): (MAIN, 0.95)}))
    policy.tripod("main", (0.0, 55.0, -12.0))
    policy.chain.identify("main")
    policy.chain.trust(0)
    held_camera = MAIN.replace(pan_rad=0.25)
    held = policy.decide(FrameObservations(0, W, H), SimpleNamespace(marking_mask=np.zeros((9, 16), bool)), pitch,
                         None, None, held=held_camera, held_confidence=0.3)
    assert held.camera is held_camera  # refined (the fake refiner echoes it at 0.8), not dropped by the gate


def test_a_camera_found_while_the_chain_is_not_trusted_is_named_by_where_it_stands():
    # A shot's chain started from the main camera's last camera refined on its first frame, taken for want of a
    # better one (not confident: its id "main" is only a guess's). A camera the search then finds standing at a
    # corner is that corner camera, with its own id: not pulled onto the main camera's tripod. Once the chain is
    # trusted, its id is the shot's, whatever a re-initialisation finds.
    fakes = Fakes({None: (CORNER, 0.95)}, guess_confidence=0.1)
    policy = _policy(fakes, search_time_share=1.0)
    policy.tripod("main", (0.0, 55.0, -12.0))
    policy.chain.identify("main")
    decision = _decide(policy, 5)
    assert decision.camera is CORNER and decision.camera_id not in (None, "main")
    assert decision.camera_id in policy.registry.untrusted  # a new id, provisional until its chain is trusted
    fakes = Fakes({None: (CORNER, 0.95)}, guess_confidence=0.1)
    policy = _policy(fakes, search_time_share=1.0)
    policy.tripod("main", (0.0, 55.0, -12.0))
    policy.chain.identify("main")
    decision = _decide(policy, 5, chain_trusted=True)
    assert decision.camera is CORNER and decision.camera_id == "main"


def test_a_court_camera_not_taken_is_looked_for_again_on_the_frame_s_faint_look_at_the_same_bar():
    """The court model finds nothing on the markings as found and CORNER on their faint look: taken when over its bar
    there (the decision says so: the frame's markings are the faint look's from then on), else the search decides on
    the markings as found. No second look without a court try this frame, nor after a court camera taken."""
    from broadtrack_graph.track.camera_ids import CameraRegistry

    looked = SimpleNamespace(marking_mask=np.ones((9, 16), bool))

    def run(faint_confidence, first=None, court_on=True):
        fakes = Fakes({OWN_POSITION: (MAIN, 0.62), None: (MAIN, 0.62)})
        seen, looks = [], []

        def court(detections, frame_size, curves):
            seen.append("faint" if detections is looked else "found")
            camera = first if detections is not looked else CORNER
            if camera is None:
                return ReinitResult(None, None, "", "nothing", tried=1)
            fakes.confidences[id(camera)] = faint_confidence if camera is CORNER else 0.9
            return ReinitResult(camera, None, "fake court")

        policy = ReinitPolicy(TrackingConfig(), fakes.search, fakes.refine, fakes.confidence,
                              CameraRegistry(known={"main": MAIN.position_m}), court=court if court_on else None)
        policy.chain.identify("main")  # mid-shot, lost: searched at its position when nothing is taken
        decision = _decide(policy, 0, faint_look=lambda: looks.append(0) or looked)
        return decision, seen, len(looks), policy.counts["court_faint_look_used"]

    decision, seen, looks, used = run(0.75)
    assert decision.camera is CORNER and decision.faint_look and not decision.searched
    assert seen == ["found", "faint"] and looks == 1 and used == 1 and "(faint look)" in decision.reason
    decision, seen, looks, used = run(0.65)  # under the court model's bar (0.7) there too
    assert decision.camera is MAIN and decision.searched and not decision.faint_look and used == 0
    assert seen == ["found", "faint"]
    decision, seen, looks, _ = run(0.75, first=MAIN)  # taken on the markings as found: no second look
    assert decision.camera is MAIN and not decision.faint_look and seen == ["found"] and looks == 0
    decision, seen, looks, _ = run(0.75, court_on=False)  # no court model: nothing to look again for
    assert decision.camera is MAIN and looks == 0


def test_the_court_models_settings_that_mirror_the_trackers_agree_with_them():
    """The court model (a lower layer: it does not read the tracker's settings) keeps its own copies of three of the
    tracker's: the bar its camera is polished from (the court bar), the confidence that settles a frame (a new shot's
    certain camera) and the margin a more confident fit needs (a new camera replacing a chain's)."""
    from broadtrack_graph.reinit.court_config import CourtConfig

    court, tracker = CourtConfig(), TrackingConfig()
    assert court.polish_from == tracker.court_accept_confidence
    assert court.look_further_below == tracker.certain_confidence
    assert court.confidence_margin == tracker.reinit_switch_margin
