"""Re-initialisation: when to search, what to try, what to accept and when to switch, in one place.

The frame loop asks :meth:`ReinitPolicy.decide` once for a frame without a trusted camera
(lost, or held at a confidence under the threshold) and gets one :class:`ReinitDecision`:
the camera to restart the solver from (or None: keep what is held / nothing found), its
confidence, the camera id it belongs to, and why. The current camera id and whether the chain is
trusted are the run's :class:`~broadtrack_graph.track.chain.Chain`'s: the policy reads them there
and keeps no copy. No I/O.

What is tried, cheapest first (for a trusted chain's held camera, the guesses only, the held camera itself among
them, or on labelled detections without a map the search at its camera's position: the court and field models and
the search place a camera from nothing, for a chain's start or a lost chain):

1. **Guesses**: the last confident camera of the current camera id (and the same camera
   moved to that camera's known position) or, when the camera id is not known yet (a new
   shot), of every camera seen so far: one local label-and-fit each on the marking map, tens
   of milliseconds (:func:`broadtrack_graph.reinit.cheap.refine_guesses`). A confident refined
   guess is taken at once and continues its camera's chain (at a shot's start, only when it
   still stands where its camera stands): this is how a camera returning after a close-up or a
   replay is recognised. Every known camera's guesses are tried on the frames of
   :class:`~broadtrack_graph.track.search_budget.TrySchedule`, as the field model is.
2. **The court model** (a marking map): a camera from the markings alone (straight lines, a circle with the line
   across it, the centre circle with a touchline), wherever it stands
   (:func:`~broadtrack_graph.reinit.court.court_reinit`, :class:`~broadtrack_graph.track.frame_tries.FrameTries`):
   taken at ``court_accept_confidence``, at ``court_grid_accept_confidence`` when the markings it explains hold two
   straight lines of each direction (:func:`court_accept_at`; at least where its chain can be trusted from it), or
   confident by the
   margin when the court camera of a frame shortly before stood in the same place with its view moved on
   (``court_agreement_view_change``: a still camera's frames show the same markings), with the id of where it stands
   (its twin when a known camera stands there); otherwise dropped. On its own
   :class:`~broadtrack_graph.track.search_budget.TrySchedule`. A new shot's court camera confident by the margin
   defers the rest for ``court_agreement_frames``: the next frames' court cameras confirm it or not.
   A lost frame whose court camera is not taken is looked at again with its faint look (the markings with the faint
   straight paint added, :mod:`~broadtrack_graph.detect.faint_lines`): the court model's camera on those, taken at
   the same bar, and the frame's markings are those from then on; the rest of the decision stays on the markings
   as found.
3. **The learned field model** (image input): its keypoints give a camera wherever it stands
   (:class:`~broadtrack_graph.reinit.field_model.ModelReinit`, tens of ms), refined on the marking
   map. Taken when confident (a new shot's camera: when certain, ``certain_confidence``), with
   the id of where it stands; else a candidate the search must beat. It tries every frame of a shot's first
   frames it cannot place (up to 10), then waits 1, 2, 4, ... frames after each
   (:class:`~broadtrack_graph.track.search_budget.TrySchedule`): a shot it cannot place costs little.
4. **The global search** in stages, when the search budget allows
   (:class:`~broadtrack_graph.track.search_route.SearchRoute`: its stages and its budget; on a marking map not at
   all with ``global_search`` off).

   * A shot whose camera is not known yet: the stages of :mod:`~broadtrack_graph.track.search_stages` (the known
     cameras, the default positions), both (a view of one camera can be explained, less well, by a camera
     elsewhere) unless the first gives a camera at ``certain_confidence`` or a known camera at its own position
     confident by the margin.
   * A shot whose camera is known (mid-shot: the camera has not moved): that camera's position, then, for a main
     camera whose chain is not trusted (a trusted chain's camera stands where its confident frames put it), the
     default positions; the first confident stage ends it.
     A trusted chain's held camera on a marking map is not searched for: the held camera refined on the map (a
     guess) is what a search at its position would find. When it drops under ``lost_confidence`` the
     chain ends and the next frame is placed from nothing.
   * Where the court model looks at the marking map (it places a camera wherever it stands, a returning one too): a
     new shot only at the known cameras' positions, for a returning camera found at its own position confident by
     the margin (its view's markings may fix it only on its tripod: a zoomed view of an arc and a touchline), a
     shot whose camera is known only at that camera's position.

Camera ids: a shot keeps the id of its first trusted camera; a camera found at a shot's start, or while its chain
is not trusted yet (its id then is only a guess's), is identified by where it stands
(:mod:`~broadtrack_graph.track.camera_naming`; :class:`~broadtrack_graph.track.camera_ids.CameraRegistry`: along and
across its line of sight): a known camera's id
when the frame, refined with the focal point at that camera's position, is explained within the margin (a tripod;
another stadium's camera at a similar place is not), else a new id when it is confident; provisional until its chain
is trusted (till then judged as a new shot's camera; forgotten at the next cut otherwise).

**A frame the shot step reads as another view** (close-up, crowd: read from colours, which a low camera's goal frame
and net, or the stands inside the grass's outline, can fool): a camera from nothing is the court model's alone, taken
at its bar, every run of it a try on its schedule (:meth:`ReinitPolicy._other_view_decision`); a refined guess, the
field model or a search would lay a camera on a close-up's few markings. A chain it starts is tracked on.

**One gate** for a chain's first camera (not a trusted chain's, whose frames are being written), whatever route
gave it: on a marking map it is kept only when the markings it explains fix it
(:func:`~broadtrack_graph.geometry.determinable.fixes_camera`, the court model's own check); a camera on its
trusted camera id's known tripod (within :data:`~broadtrack_graph.track.camera_ids.ON_TRIPOD_M`) has its focal point
known, and is kept when they fix its focal length and angles with a constraint to spare at the court model's bar
(exactly, at its exact-fit bar), and a searched camera off that tripod is refitted on it
(:mod:`~broadtrack_graph.track.known_tripod`).

**One margin**, ``reinit_switch_margin``: the held camera of a trusted chain (its frames are being written) is
replaced only by a camera that much more confident, confident or not (one frame's camera just over the threshold
in a blurred sweep is as often wrong as the held one); a camera that is not confident replaces a refined guess or
the search's camera only by the margin, a confident camera replaces an unconfident one; the chain of a
new shot's camera is trusted from a frame confident by the margin (:attr:`ReinitDecision.new_camera`).
All thresholds are the run's :class:`~broadtrack_graph.track.config.TrackingConfig`.

**The search budget** (:mod:`~broadtrack_graph.track.search_budget`, in frames: the same cameras on any machine): a
known camera lost mid-shot is searched again after 1, 2, 4, ... frames; a shot whose camera is not known, at its first
frame, then for about ``search_time_share`` of the time while nothing is found. A search finds
something when its camera is trusted from its frame (confident by the margin for a new shot's camera); else the wait
grows. A cut or a view change (:meth:`ReinitPolicy.new_stretch`) and a confident frame restart it.
"""

from __future__ import annotations

from dataclasses import replace
from typing import Callable

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.determinable import determinability, fixes_camera
from broadtrack_graph.reinit.scoring import ReinitResult
from broadtrack_graph.track.camera_ids import CameraRegistry
from broadtrack_graph.track.camera_naming import CameraNaming
from broadtrack_graph.track.chain import Chain
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.frame_tries import CourtCamera, FrameTries, ModelCamera, court_accept_at
from broadtrack_graph.track.known_tripod import fixed_on_known_tripod, onto_its_tripod
from broadtrack_graph.track.reinit_decision import Candidate, ReinitDecision
from broadtrack_graph.track.search_budget import TrySchedule
from broadtrack_graph.track.search_route import SearchRoute
from broadtrack_graph.track.search_stages import search_plan

Search = Callable[..., ReinitResult]
"""``(observations, detections, pitch, positions or None, curves, sampling) -> ReinitResult``: one global search."""
Refiner = Callable[..., ReinitResult]
"""``(guesses [(label, Camera)], detections, curves, hold_position=False) -> ReinitResult``: the best guess after a
local fit (``hold_position``: each guess's focal point held where it stands)."""

Confidence = Callable[..., float | None]
"""``(camera, observations, detections, curves, sampling) -> confidence``: the tracker's confidence."""

class ReinitPolicy:
    """The one re-initialisation decision of a run (module docstring).

    Args:
        config: thresholds and budget (``confidence_threshold``, ``lost_confidence``, ``reinit_switch_margin``,
            ``search_*``, ``max_search_backoff``, ``max_guess_age_frames``, ``cheap_reinit``).
        search: one global search (:data:`Search`).
        refine: refines guesses on the frame's marking map (:data:`Refiner`).
        confidence: the tracker's confidence (:data:`Confidence`); every camera is judged by it.
        registry: the run's cameras by id (a new one by default).
        search_positions: candidate focal points given to the run (``--reinit-position``): searched
            instead of the default stages.
        model: a camera from the learned field model (:data:`ModelCamera`), or None.
        court: a camera from the marking map wherever it stands (:data:`CourtCamera`), or None.
        chain: the run's chain (:class:`~broadtrack_graph.track.chain.Chain`), read for its camera id and its
            trust, never copied (default: a chain of its own, on the registry: a new shot's, as the placement
            benchmarks ask).
    """

    def __init__(self, config: TrackingConfig, search: Search, refine: Refiner, confidence: Confidence,
                 registry: CameraRegistry | None = None, search_positions=None,
                 model: ModelCamera | None = None, court: CourtCamera | None = None,
                 chain: Chain | None = None) -> None:
        self.config = config
        self.refine = refine
        self.confidence = confidence
        self.registry = registry or CameraRegistry()
        self.chain = chain or Chain(config, self.registry)
        self.search_positions = None if search_positions is None else [tuple(p) for p in search_positions]
        self._frame = None  # (detections, curves, score) of the frame decided on
        self.held_schedule = TrySchedule()  # a trusted chain's held camera under the threshold: when it is tried
        self.counts = {"guess_used": 0, "court_used": 0, "court_faint_look_used": 0, "court_other_view_used": 0,
                       "court_tried": 0, "model_used": 0,
                       "model_tried": 0, "global": 0, "stages": 0, "skipped_by_budget": 0}
        self.searches = SearchRoute(config, search, self.registry, self.counts)
        self.tries = FrameTries(config, self.registry, refine, model, court, self.counts)
        self.naming = CameraNaming(config, self.registry, self.chain, refine)

    # ----------------------------------------------------------------- what the loop tells

    def new_stretch(self) -> None:
        """A cut or a view change (the chain's camera is unknown: :meth:`Chain.new_stretch`): a never trusted id is
        forgotten; the next search is paid now."""
        self.registry.forget_untrusted()
        self.searches.new_stretch()
        self.tries.new_stretch()
        self.held_schedule.new_stretch()

    def confident(self, frame_index: int, camera: Camera) -> None:
        """A frame whose camera the tracker trusts: the guess of the chain's camera id from now on; the budget
        restarts."""
        if self.chain.camera_id is not None:
            self.registry.trust(self.chain.camera_id, frame_index, camera)
        self.searches.confident()
        self.tries.confident()
        self.held_schedule.confident()

    def tripod(self, camera_id: str, T_w) -> None:
        """A tripod fitted or given for a camera: its position identifies the camera from now on."""
        self.registry.update(camera_id, T_w)

    # ----------------------------------------------------------------- the decision

    def asks_about_held(self, frame_index: int) -> bool:
        """Whether a trusted chain's camera under the threshold is tried on this frame. After a try that does not
        replace it, the next waits 1, 2, 4, up to 8 frames (:class:`TrySchedule`); a confident frame, a replacement
        or a cut restarts the wait. Frames between are written as solved (the chain is trusted)."""
        return self.held_schedule.allows(frame_index)

    def decide(self, observations, detections, pitch, curves, sampling, held: Camera | None = None,
               held_confidence: float | None = None, image: np.ndarray | None = None,
               faint_look=None, other_view: bool = False) -> ReinitDecision:
        """A camera for a frame without a trusted one (module docstring; arguments: :meth:`_decide`)."""
        decision = self._decide(observations, detections, pitch, curves, sampling, held, held_confidence, image,
                                faint_look, other_view)
        if held is not None and self.chain.trusted:
            self.held_schedule.tried(observations.frame_index, decision.camera is not None)
        mask = getattr(self._frame[0] if decision.faint_look else detections, "marking_mask", None)
        if decision.camera is not None and not self.chain.trusted and mask is not None and pitch is not None:
            # A chain's first camera, whatever gave it, is kept only if the markings it explains fix it (on its known
            # tripod, with its focal point known: track/known_tripod.py).
            fixed = determinability(decision.camera, pitch, explained_by=mask)
            if not fixes_camera(fixed) and not fixed_on_known_tripod(self.registry, self.config, decision.camera_id,
                                                                     decision.camera, decision.confidence, fixed):
                return ReinitDecision(None, None, None, False, decision.searched, "the markings the camera explains "
                                      f"do not fix it ({decision.reason})")
        return decision

    def _decide(self, observations, detections, pitch, curves, sampling, held: Camera | None = None,
                held_confidence: float | None = None, image=None, faint_look=None,
                other_view: bool = False) -> ReinitDecision:
        """The decision, before the held camera's schedule hears of it.

        Args:
            observations, detections: the frame's (detections None for a detections file).
            pitch, curves, sampling: the template.
            held: the camera the solver holds for this frame (confidence under the threshold), None when lost.
            held_confidence: its confidence.
            image: the frame (H, W, 3) BGR, for the field model; None: no model this frame.
            faint_look: ``() -> Detections | None``: the frame's detections with their faint look (detect.faint_lines;
                None: it adds nothing), for the court model's second look; None: no second look.
            other_view: the shot step reads the frame as another view (a close-up, a crowd): a camera from nothing is
                the court model's alone (:meth:`_other_view_decision`).

        The chain's camera id and its trust (a trusted chain's held camera costs smoothing to switch) are read from
        :attr:`chain`.
        """
        chain_id = self.chain.camera_id
        i = observations.frame_index
        threshold, margin = self.config.confidence_threshold, self.config.reinit_switch_margin
        score = lambda camera: self.confidence(camera, observations, detections, curves, sampling)  # noqa: E731
        self._frame = (detections, curves, score)  # the frame whose cameras are named (CameraNaming.id_of)
        with_map = detections is not None and getattr(detections, "marking_mask", None) is not None
        # A trusted chain's held camera is re-examined by what knows its camera: itself and the chain's last confident
        # camera refined on the map (a search at its position without a map); the single-frame calibrators, which
        # place a camera from nothing, are for a chain's start.
        from_nothing = not (held is not None and self.chain.trusted)
        # The shot's camera not trusted yet (no id, or an untrusted first camera's): judged as at the shot's start.
        untrusted = chain_id is None or chain_id in self.registry.untrusted
        new_camera = untrusted and self.search_positions is None and with_map
        if other_view and from_nothing:
            return self._other_view_decision(observations, detections, curves, score, held, held_confidence,
                                             new_camera)
        guess = self.tries.refined_guess(i, chain_id, detections, curves, score,
                                         held if with_map and not from_nothing else None)
        if guess is not None and guess.confidence >= threshold:
            self.counts["guess_used"] += 1
            return self._switch_or_keep(guess.result, guess.confidence, guess.camera_id, True, False, guess.label,
                                        held, held_confidence)
        candidate = guess  # the best camera so far that is not confident
        if with_map and not from_nothing:
            # The held camera refined on the map stands in for the search at its position, at a tenth of its cost.
            if candidate is not None:
                return self._candidate_decision(candidate, False, "", held, held_confidence, new_camera)
            return ReinitDecision(None, None, None, False, False, "no refined guess of the held camera")
        court = self.tries.court_camera(observations, detections, curves, score) if from_nothing else None
        if court is not None and (court.confidence >= court_accept_at(self.config, court.result, new_camera)
                                  or court.agrees):
            # The primary route: a camera from the markings alone, taken when sure enough to skip the search (or
            # confident by the margin on two frames that agree). Otherwise dropped, not kept as a candidate: a
            # wrong camera the solver held would block the search's.
            self.counts["court_used"] += 1
            return self._court_decision(court, court.label, held, held_confidence, new_camera)
        if from_nothing:
            again = self._second_look(observations, curves, sampling, faint_look, held, held_confidence, new_camera)
            if again is not None:
                return again
        modelled = self.tries.model_camera(i, image, detections, curves, score) if from_nothing else None
        if modelled is not None:
            # A new shot's camera is taken at once only when certain, as a search stage's is: a focal length /
            # distance trade-off of the right view can reach the margin (docs/MODEL.md, "Figures").
            if modelled.confidence >= (self.config.certain_confidence if new_camera else threshold):
                self.counts["model_used"] += 1
                camera_id = self.naming.id_of(modelled.result, modelled.confidence, self._frame)
                return self._decision(modelled.result, modelled.confidence, camera_id, False, False, modelled.label,
                                      held, held_confidence, new_camera)
            if candidate is None or modelled.confidence > candidate.confidence:
                candidate = modelled  # its camera id is given only if it is taken
        if new_camera and self.tries.court_may_agree(i):
            # A court camera confident by the margin is confirmed (or not) by the next frames' before a search is paid.
            return ReinitDecision(None, None, None, False, False, "court model: waiting for the next frames' court "
                                  f"cameras to agree ({court.confidence if court else 0.0:.2f} on this frame)")
        known = chain_id is not None and chain_id in self.registry.positions
        plan = search_plan(self.registry.positions, chain_id, self.search_positions, with_map,
                           held_trusted=held is not None and self.chain.trusted,
                           court_looks=self.tries.court is not None)
        if not plan.stages:
            why = "no search: the court model looks wherever the camera stands"
        else:
            why = self.searches.not_searched_because(i, known) if with_map else None
        if why is not None:
            if candidate is not None:
                return self._candidate_decision(candidate, False, f" ({why})", held, held_confidence, new_camera)
            return ReinitDecision(None, None, None, False, False, why)
        # found: a camera its chain is trusted from (a new shot's camera: by the margin)
        found, found_confidence, label = self.searches.run(
            plan, i, known, with_map, threshold + (margin if new_camera else 0.0),
            (observations, detections, pitch, curves, sampling), score)
        if candidate is not None and (found is None or (found_confidence < threshold
                                                        and found_confidence <= candidate.confidence + margin)):
            # Nothing confident found: the candidate (a refined guess: a confident camera's continuation; or the
            # model's camera) stays unless the search's camera is clearly better.
            return self._candidate_decision(candidate, True, "; the search found nothing better", held,
                                            held_confidence, new_camera)
        if found is None:
            return ReinitDecision(None, None, None, False, True, f"global search: {label}")
        searched = found
        found, found_confidence = onto_its_tripod(self.registry, self.config, self.refine, found, found_confidence,
                                                  detections, pitch, curves, score)
        label += f", {found.hypothesis}" if found is not searched else ""
        camera_id = self.naming.id_of(found, found_confidence, self._frame)
        return self._decision(found, found_confidence, camera_id, False, True, label, held, held_confidence, new_camera)

    def _second_look(self, observations, curves, sampling, faint_look, held, held_confidence,
                     new_camera: bool) -> ReinitDecision | None:
        """The court model's second look at a frame it tried and did not place (on its schedule), when asked: its
        markings with the faint straight paint added (``faint_look()``), for the court model alone (the rest of the
        decision stays on the markings as found); its camera taken at the same bar (the decision: the camera, or the
        held camera kept). None: no camera taken."""
        looked = faint_look() if faint_look is not None and self.tries.court_ran_on == observations.frame_index \
            else None
        if looked is None:
            return None
        looked_score = lambda camera: self.confidence(camera, observations, looked, curves, sampling)  # noqa: E731
        again = self.tries.court_camera_again(observations, looked, curves, looked_score)
        if again is None or again.confidence < court_accept_at(self.config, again.result, new_camera):
            return None
        self.counts["court_faint_look_used"] += 1
        self._frame = (looked, curves, looked_score)
        decision = self._court_decision(again, again.label + " (faint look)", held, held_confidence, new_camera)
        return replace(decision, faint_look=True) if decision.camera is not None else decision

    def _other_view_decision(self, observations, detections, curves, score, held, held_confidence,
                             new_camera: bool) -> ReinitDecision:
        """A camera from nothing for a frame the shot step reads as another view: its markings may still place one
        (a low camera's goal frame, or the stands inside the grass's outline, read as a close-up), the court model's
        alone, taken at its bar, without its second look (it would run on most tries of a close-up); every run of it
        counts against its schedule (a close-up's shot: its first frames, then more and more rarely). A refined guess,
        the field model or a search would lay a camera on a close-up's few markings."""
        court = self.tries.court_camera(observations, detections, curves, score, every_run_counts=True)
        if court is None or court.confidence < court_accept_at(self.config, court.result, new_camera):
            found = "no camera" if court is None else f"a camera at {court.confidence:.2f}, under its bar"
            return ReinitDecision(None, None, None, False, False, f"court model: {found}")
        self.counts["court_other_view_used"] += 1
        return self._court_decision(court, court.label, held, held_confidence, new_camera)

    def _court_decision(self, court, label: str, held, held_confidence, new_camera: bool) -> ReinitDecision:
        """The decision for a court camera taken at its bar (a
        :class:`~broadtrack_graph.track.reinit_decision.CourtCandidate`), named by where it stands."""
        camera_id = self.naming.id_of(court.result, court.confidence, self._frame)
        return self._decision(court.result, court.confidence, camera_id, False, False, label, held, held_confidence,
                              new_camera)

    def looks_at_other_view(self, frame_index: int) -> bool:
        """Whether the court model looks at this frame, which the shot step reads as another view (its schedule)."""
        return self.tries.court_may_run(frame_index)

    def _candidate_decision(self, candidate: Candidate, searched: bool, why: str, held, held_confidence,
                            new_camera: bool) -> ReinitDecision:
        """The decision for the best camera so far that is not confident, ``why`` appended to its label."""
        continues = candidate.continues_chain
        camera_id = candidate.camera_id if continues else self.naming.id_of(candidate.result, candidate.confidence,
                                                                            self._frame)
        return self._decision(candidate.result, candidate.confidence, camera_id, continues, searched,
                              candidate.label + why, held, held_confidence, new_camera and not continues)

    def _decision(self, result: ReinitResult, confidence: float, camera_id: str | None, continues_chain: bool,
                  searched: bool, reason: str, held: Camera | None, held_confidence: float | None,
                  new_camera: bool) -> ReinitDecision:
        """:meth:`_switch_or_keep`, the decision marked ``new_camera`` when it switches to a new shot's camera."""
        decision = self._switch_or_keep(result, confidence, camera_id, continues_chain, searched, reason, held,
                                        held_confidence)
        return replace(decision, new_camera=new_camera) if decision.camera is not None else decision

    def _switch_or_keep(self, result: ReinitResult, confidence: float, camera_id: str | None, from_guess: bool,
                        searched: bool, reason: str, held: Camera | None,
                        held_confidence: float | None) -> ReinitDecision:
        """The new camera, or None when the held camera stays (the one margin, module docstring: a trusted chain's
        held camera is switched only by the margin)."""
        if held is not None and held_confidence is not None:
            needed = held_confidence + (self.config.reinit_switch_margin if self.chain.trusted else 0.0)
            if not confidence > needed:
                return ReinitDecision(None, None, None, False, searched,
                                      f"kept the held camera ({held_confidence:.2f}): {reason} scored {confidence:.2f}")
        return ReinitDecision(result.camera, confidence, camera_id, from_guess, searched, reason)

