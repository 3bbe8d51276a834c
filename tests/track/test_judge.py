"""The judge of a solved frame (broadtrack_graph.track.judge): each verdict from hand-set facts, no solver."""

from __future__ import annotations

from dataclasses import replace

import pytest

from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.judge import Action, FrameFacts, Verdict, judge

CONFIG = TrackingConfig(confidence_threshold=0.5, lost_confidence=0.2, reinit_switch_margin=0.1)
TRUSTED = FrameFacts(0.8, True, chain_trusted=True, trust_at=0.5)  # a trusted chain's frame at 0.8
NEW_CHAIN = FrameFacts(0.8, True, chain_trusted=False, trust_at=0.6, reinitialised=True, from_marking_map=True)


def test_a_confident_frame_is_written_and_trusts_its_chain():
    verdict = judge(TRUSTED, CONFIG)
    assert verdict == Verdict(Action.WRITE, "confidence 0.80 at the bar 0.50", trusted=True, confident=True)
    # A new shot's camera: at its raised bar (0.6) the chain is trusted from this frame.
    verdict = judge(NEW_CHAIN, CONFIG)
    assert verdict.action is Action.WRITE and verdict.trusted and verdict.confident and not verdict.withholds_camera
    assert verdict.reason == "confidence 0.80 at the bar 0.60"


def test_a_frame_carried_on_the_motion_prior_trusts_the_chain_but_is_no_guess():
    verdict = judge(replace(TRUSTED, carried=True), CONFIG)
    assert verdict.action is Action.WRITE and verdict.trusted and not verdict.confident


def test_no_camera_or_one_under_the_bar_asks_for_a_re_initialisation():
    no_camera = judge(FrameFacts(None, False, True, 0.5), CONFIG)
    assert no_camera == Verdict(Action.REINITIALISE, "no camera from the solver")
    low = judge(replace(TRUSTED, confidence=0.45), CONFIG)
    assert low == Verdict(Action.REINITIALISE, "confidence 0.45 below 0.50")
    # An untrusted chain's bar is its own (a new shot's camera: the threshold plus the margin).
    assert judge(FrameFacts(0.55, True, False, 0.6), CONFIG).action is Action.REINITIALISE
    # A frame re-initialised before it was solved is not re-initialised again for being low.
    assert judge(replace(NEW_CHAIN, confidence=0.3), CONFIG).action is not Action.REINITIALISE
    # Not scored (nothing to score it on): nothing to re-initialise for.
    assert judge(FrameFacts(None, True, True, 0.5), CONFIG).action is Action.WRITE


def test_lost_when_the_policy_found_nothing():
    # No camera, and the policy found none: the chain ends, the record keeps the solver's reason.
    verdict = judge(FrameFacts(None, False, True, 0.5, asked=True), CONFIG)
    assert verdict.action is Action.LOST and not verdict.withholds_camera
    # The held camera under the lost confidence, and nothing replaced it.
    verdict = judge(replace(TRUSTED, confidence=0.1, asked=True), CONFIG)
    assert verdict == Verdict(Action.LOST, "confidence 0.10 below 0.20 and re-initialisation failed",
                              withholds_camera=True)
    # A frame re-initialised before it was solved whose solved camera fell under it.
    verdict = judge(replace(NEW_CHAIN, confidence=0.15), CONFIG)
    assert verdict.action is Action.LOST and verdict.withholds_camera
    assert verdict.reason == "confidence 0.15 below 0.20 and re-initialisation failed"


def test_a_camera_the_policy_put_in_is_never_lost_at_once():
    replaced = FrameFacts(0.1, True, False, 0.5, asked=True, replaced=True)
    assert judge(replaced, CONFIG).action is Action.WRITE  # (no marking map: written, under the bar)


def test_the_held_camera_the_policy_kept_is_written_in_its_trusted_chain():
    verdict = judge(replace(TRUSTED, confidence=0.45, asked=True), CONFIG)
    assert verdict == Verdict(Action.WRITE, "confidence 0.45 below the bar 0.50")


def test_a_marking_map_chain_without_a_frame_at_its_bar_is_held_back():
    facts = replace(NEW_CHAIN, confidence=0.55)  # above the threshold, under the new camera's bar (0.6)
    verdict = judge(facts, CONFIG)
    assert verdict == Verdict(Action.HOLD_BACK, "confidence 0.55 below 0.60 and no confident frame since the "
                              "re-initialisation; camera not written", withholds_camera=True)
    # Labelled lines or keypoints (no marking map) name what they show: written, and a guess (at the threshold).
    written = judge(replace(facts, from_marking_map=False), CONFIG)
    assert written.action is Action.WRITE and not written.trusted and written.confident
    # After the policy kept it (it found no better camera) it is still held back.
    assert judge(replace(facts, confidence=0.3, reinitialised=False, asked=True), CONFIG).action is Action.HOLD_BACK


@pytest.mark.parametrize("confidence", [0.5, 0.6, 0.99])
def test_every_written_camera_at_the_threshold_is_a_guess(confidence):
    verdict = judge(replace(TRUSTED, confidence=confidence), CONFIG)
    assert verdict.action is Action.WRITE and verdict.confident and verdict.trusted


def test_a_camera_under_the_threshold_in_a_fast_sweep_is_held_back():
    limit = CONFIG.max_unsure_motion_px
    fast = replace(TRUSTED, confidence=0.45, asked=True, image_motion_px=limit + 1.0)
    verdict = judge(fast, CONFIG)
    assert verdict == Verdict(Action.HOLD_BACK, f"confidence 0.45 below 0.50 while the image moves {limit + 1.0:.0f} "
                              "px a frame; camera not written", withholds_camera=True)
    # As slow as that or slower, or at the threshold however fast: written.
    assert judge(replace(fast, image_motion_px=limit), CONFIG).action is Action.WRITE
    assert judge(replace(fast, image_motion_px=None), CONFIG).action is Action.WRITE
    at_threshold = judge(replace(fast, confidence=0.5), CONFIG)
    assert at_threshold.action is Action.WRITE and at_threshold.confident


def test_a_fast_sweep_whose_crossing_markings_are_not_found_is_held_back_at_any_confidence():
    limit = CONFIG.max_unsure_motion_px
    sweep = replace(TRUSTED, confidence=0.8, image_motion_px=limit + 30.0, recall_across_motion=0.05)
    verdict = judge(sweep, CONFIG)
    assert verdict == Verdict(Action.HOLD_BACK, f"the markings crossing the image's motion ({limit + 30.0:.0f} px a "
                              "frame) not found (recall 0.05); camera not written", withholds_camera=True)
    # Found at the bar, or not measured, or a slower image: written.
    bar = CONFIG.min_recall_across_motion
    assert judge(replace(sweep, recall_across_motion=bar), CONFIG).action is Action.WRITE
    assert judge(replace(sweep, recall_across_motion=None), CONFIG).action is Action.WRITE
    assert judge(replace(sweep, image_motion_px=limit), CONFIG).action is Action.WRITE


def test_online_with_no_tripod_a_camera_under_the_tripods_bar_is_held_back_not_dropped():
    unheld = replace(TRUSTED, confidence=0.55, place_held=False)  # under 0.6, over the threshold 0.5
    verdict = judge(unheld, CONFIG)
    assert verdict.action is Action.HOLD_BACK and verdict.withholds_camera
    assert verdict.reason == ("confidence 0.55 below 0.60 with no tripod holding the focal point, most of the chain's "
                              "frames under it; camera not written")
    # Otherwise rule 3's verdict: the chain goes on, trusted, and the camera stays its id's guess.
    assert verdict.trusted and verdict.confident
    # Held by a tripod, the same frame is written; at the tripod's bar it is written without one.
    assert judge(replace(unheld, place_held=True), CONFIG) == Verdict(
        Action.WRITE, "confidence 0.55 at the bar 0.50", trusted=True, confident=True)
    assert judge(replace(unheld, confidence=0.6), CONFIG).action is Action.WRITE
    # Rule 6's camera (mid-chain under the threshold, nothing better found) is held back too, and never trusts.
    low = judge(replace(unheld, confidence=0.45, asked=True), CONFIG)
    assert low.action is Action.HOLD_BACK and not low.trusted and not low.confident
    # The bar is the tripod's own.
    assert judge(unheld, replace(CONFIG, tripod_fit_min_confidence=0.5)).action is Action.WRITE
