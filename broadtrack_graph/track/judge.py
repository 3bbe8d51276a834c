"""The judge of a solved frame: from the facts, a verdict (write, hold back, re-initialise, lost) and why.

The frame loop scores the frame's camera with the tracker's confidence and asks :func:`judge`; it applies the
:class:`Verdict` (:meth:`~broadtrack_graph.track.frame_loop.TrackingRun.process`). The rules, with ``T`` the
confidence threshold, ``L`` the lost confidence and the chain's bar ``T`` once the chain is trusted, else its
``trust_at`` (:class:`~broadtrack_graph.track.chain.Chain`):

1. **Re-initialise** a frame the solver gave no camera, or one under the bar that was not re-initialised before
   it was solved (the policy is asked once; the judge is then asked again with what it found). A trusted chain's
   camera is asked about on the frames the policy's schedule gives
   (:meth:`~broadtrack_graph.track.reinit_policy.ReinitPolicy.asks_about_held`); on the others the frame loop
   judges it as asked, with nothing found.
2. **Lost**: no camera even after the policy; or a camera under ``L`` that was re-initialised before it was solved,
   or that the policy could not replace. The chain ends; a camera is not written.
3. **Write** a camera at ``T`` and at the chain's bar: the chain is trusted from it.
4. **Hold back** a camera of a chain started from the unlabelled marking map that has had no frame at its bar:
   it seeds the next frame, it is not written (a map search can settle on a wrong camera that still explains part
   of the map; labelled lines and keypoints name what they show).
5. **Hold back** a camera while the image moves more than ``max_unsure_motion_px`` a frame
   (:func:`~broadtrack_graph.geometry.tripod.image_motion_px` from the chain's previous frame) when it is under
   ``T``, or when the markings that cross the motion are not found (their recall under
   ``min_recall_across_motion``, :func:`~broadtrack_graph.reinit.confidence.recall_across_motion`): motion blur
   smears exactly those, and a camera that only the markings along the sweep explain is not checked along it
   (it may be off by tens of pixels along the sweep at any confidence).
6. **Write** any other camera (mid-chain under ``T``: the policy found no better one).
7. **Hold back** a camera rule 3 or 6 would write when it is under the tripod's own bar (``tripod_fit_min_confidence``:
   the confidence a frame needs to place the tripod) while its focal point is not held: no tripod holds it (online,
   before the provisional one) and fewer than half the chain's scored frames, this one counted, reached that bar
   (:meth:`~broadtrack_graph.track.chain.Chain.mostly_sure`). On such frames a camera metres off along its line of
   sight, with another focal length and pan, explains the markings about as well (the depth of a narrow view,
   degraded markings): only the camera's place tells them apart, and a chain mostly under the bar has not shown it.
   The verdict is otherwise rule 3's or 6's (the chain goes on, trusted, its camera its id's guess), so only what is
   written changes (in every mode: the offline modes' first pass is online).

A written camera at ``T`` (not a frame carried on the motion prior) is its camera id's guess from now on
(:attr:`Verdict.confident`). Pure: no I/O, no solver.
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from broadtrack_graph.track.config import TrackingConfig


class Action(Enum):
    """What the frame loop does with the frame's camera."""

    WRITE = "write"  # written; the next frame is linked to it
    HOLD_BACK = "hold back"  # seeds the next frame, not written
    REINITIALISE = "re-initialise"  # ask the re-initialisation policy, then the judge again
    LOST = "lost"  # not written; the chain ends, the next frame is re-initialised


@dataclass(frozen=True)
class FrameFacts:
    """What the judge weighs for one frame."""

    confidence: float | None  # the tracker's confidence of the frame's camera (None: no camera, or not scored)
    has_camera: bool  # the frame has a camera (the solver's, or the re-initialisation's)
    chain_trusted: bool  # the chain has had a frame at its bar (Chain.trusted)
    trust_at: float  # the bar of a chain not trusted yet (Chain.trust_at)
    reinitialised: bool = False  # the frame began lost: its camera was re-initialised before it was solved
    asked: bool = False  # the re-initialisation policy was asked for the solved frame ...
    replaced: bool = False  # ... and its camera replaced the solver's
    from_marking_map: bool = False  # the frame's detections carry the unlabelled marking map
    carried: bool = False  # the frame is carried on the motion prior: it claims no camera
    image_motion_px: float | None = None  # how far the image moved from the chain's previous frame (960 wide; None:
    #                                       no previous frame, or the camera was re-initialised)
    recall_across_motion: float | None = None  # the recall of the markings crossing that motion (None: not measured)
    place_held: bool = True  # the chain's focal point is held: a tripod (fitted, given or provisional), or half the
    #                          chain's scored frames at the tripod's bar (rule 7)


@dataclass(frozen=True)
class Verdict:
    """The judge's verdict on one frame.

    action: what the frame loop does (:class:`Action`).
    reason: one line, why.
    withholds_camera: the frame's record gets no camera, the status ``failed`` and ``reason`` as its reason
        (otherwise the record keeps its status and reason: the solver's for a frame without a camera).
    trusted: the chain is trusted from this frame.
    confident: a written camera at the threshold: its camera id's guess from now on (the search budget restarts).
    """

    action: Action
    reason: str
    withholds_camera: bool = False
    trusted: bool = False
    confident: bool = False


def judge(facts: FrameFacts, config: TrackingConfig) -> Verdict:
    """The verdict on a frame's camera (the rules: module docstring).

    Args:
        facts: the frame's camera, its confidence and the chain's trust.
        config: the thresholds (``confidence_threshold``, ``lost_confidence``, ``max_unsure_motion_px``,
            ``tripod_fit_min_confidence``).
    """
    verdict = _judge_chain(facts, config)
    confidence = facts.confidence
    if verdict.action is Action.WRITE and not facts.place_held and confidence is not None \
            and confidence < config.tripod_fit_min_confidence:
        return Verdict(Action.HOLD_BACK, f"confidence {confidence:.2f} below {config.tripod_fit_min_confidence:.2f} "
                       "with no tripod holding the focal point, most of the chain's frames under it; camera not "
                       "written", withholds_camera=True, trusted=verdict.trusted, confident=verdict.confident)
    return verdict


def _judge_chain(facts: FrameFacts, config: TrackingConfig) -> Verdict:
    """Rules 1-6 (module docstring)."""
    threshold, lost_at = config.confidence_threshold, config.lost_confidence
    confidence = facts.confidence
    bar = threshold if facts.chain_trusted else facts.trust_at
    if not facts.asked:
        if not facts.has_camera:
            return Verdict(Action.REINITIALISE, "no camera from the solver")
        if confidence is not None and confidence < bar and not facts.reinitialised:
            return Verdict(Action.REINITIALISE, f"confidence {confidence:.2f} below {bar:.2f}")
    if not facts.has_camera:
        return Verdict(Action.LOST, "no camera and re-initialisation failed")
    if (facts.reinitialised or facts.asked) and not facts.replaced and confidence is not None \
            and confidence < lost_at:
        return Verdict(Action.LOST, f"confidence {confidence:.2f} below {lost_at:.2f} and re-initialisation failed",
                       withholds_camera=True)
    unsure_motion = facts.image_motion_px is not None and facts.image_motion_px > config.max_unsure_motion_px
    if unsure_motion and facts.recall_across_motion is not None \
            and facts.recall_across_motion < config.min_recall_across_motion:
        return Verdict(Action.HOLD_BACK, f"the markings crossing the image's motion ({facts.image_motion_px:.0f} px a "
                       f"frame) not found (recall {facts.recall_across_motion:.2f}); camera not written",
                       withholds_camera=True)
    if confidence is not None and confidence >= max(threshold, 0.0 if facts.chain_trusted else facts.trust_at):
        return Verdict(Action.WRITE, f"confidence {confidence:.2f} at the bar {max(bar, threshold):.2f}",
                       trusted=True, confident=not facts.carried)
    if confidence is not None and not facts.chain_trusted and facts.from_marking_map:
        return Verdict(Action.HOLD_BACK, f"confidence {confidence:.2f} below {facts.trust_at:.2f} and no confident "
                       "frame since the re-initialisation; camera not written", withholds_camera=True)
    if confidence is not None and confidence < threshold and unsure_motion:
        return Verdict(Action.HOLD_BACK, f"confidence {confidence:.2f} below {threshold:.2f} while the image moves "
                       f"{facts.image_motion_px:.0f} px a frame; camera not written", withholds_camera=True)
    reason = "not scored" if confidence is None else \
        f"confidence {confidence:.2f} below the bar {max(bar, threshold):.2f}"
    return Verdict(Action.WRITE, reason, confident=confidence is not None and confidence >= threshold
                   and not facts.carried)
