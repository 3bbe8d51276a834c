"""The per-frame loop of a tracking run, read like GTSAM's iSAM2 example: predict, observe, solve, judge.

One loop serves every input (frames with a detector, a detections file, or both). Per frame:

1. **predict** the camera from the last ones (:mod:`~broadtrack_graph.track.prediction`);
2. **observe**: the markings named with it and optical flow from the previous frame
   (:class:`~broadtrack_graph.track.observe.FrameObserver`);
3. **solve**: the streaming solver (iSAM2 online, or the fixed-lag smoother) adds the frame,
   restarted from a re-initialised camera when the track was lost;
4. **judge**: the confidence of the camera, weighed by the judge (:func:`~broadtrack_graph.track.judge.judge`),
   whose verdict the loop applies: write the camera, hold it back, or re-initialise the frame: the one
   re-initialisation policy (:class:`~broadtrack_graph.track.reinit_policy.ReinitPolicy`) says what it found and
   why, with the camera id (the broadcast camera) it belongs to, and the judge is asked again; a lost frame ends
   the chain;
5. every record that became final is written at once, in frame order
   (:class:`~broadtrack_graph.track.records.RecordQueue`): an interrupted run keeps every frame.

The chain (the frames linked since a re-initialisation), its camera id and the trust it has earned have one
owner, :class:`~broadtrack_graph.track.chain.Chain`; the policy reads it, the judge is given its trust, the loop
tells it what happened. The shot step (:mod:`broadtrack_graph.track.shot_stream`) annotates image frames: a cut
breaks the chain and starts a stretch whose camera is found again; a frame it reads as another view (close-up,
crowd) gets the status ``other-view`` and no camera unless the court model, which alone looks at it, places one.
Each camera id has its own tripod (:mod:`~broadtrack_graph.track.online_tripod`). Whole runs and the offline modes:
:mod:`broadtrack_graph.track.passes`; the frames fed to a run, decoded and marked ahead in a background thread:
:mod:`broadtrack_graph.track.feed`.
"""

from __future__ import annotations

import time
from collections import deque
from dataclasses import asdict, replace
from pathlib import Path

import numpy as np

from broadtrack_graph.detect.detector import Detections
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.template import TemplateSampling, fitting_curves
from broadtrack_graph.geometry.tripod import image_motion_px
from broadtrack_graph.graph.estimates import FrameEstimate
from broadtrack_graph.graph.streaming import StreamingSolver
from broadtrack_graph.io.run_folder import RunFolder
from broadtrack_graph.io.track_writer import TrackWriter
from broadtrack_graph.reinit.cheap import refine_guesses
from broadtrack_graph.reinit.court import court_reinit
from broadtrack_graph.reinit.field_model import model_reinit_for
from broadtrack_graph.reinit.frame import frame_recall_across_motion
from broadtrack_graph.track.backfill import Backfill
from broadtrack_graph.track.camera_ids import CameraRegistry
from broadtrack_graph.track.chain import Chain
from broadtrack_graph.track.inputs import FrameInput
from broadtrack_graph.track.judge import Action, FrameFacts, judge
from broadtrack_graph.track.observe import FrameObserver
from broadtrack_graph.track.online_tripod import OnlineTripod
from broadtrack_graph.track.prediction import predicted_camera
from broadtrack_graph.track.records import PendingFrame, RecordQueue
from broadtrack_graph.track.reinit_decision import ReinitDecision
from broadtrack_graph.track.reinit_policy import ReinitPolicy
from broadtrack_graph.track.result import RunResult
from broadtrack_graph.track.run_context import RunContext
from broadtrack_graph.types.observations import FrameObservations
from broadtrack_graph.types.status import FrameStatus


class TrackingRun:
    """One tracking run over a stream of :class:`FrameInput` (see the module docstring).

    Args:
        width_px, height_px: input resolution.
        out_dir: run folder (cameras/, track.jsonl, summary.json, tripod.json).
        context: what the run is given (:class:`~broadtrack_graph.track.run_context.RunContext`: options, the
            detector, known tripods, the solver, search and confidence, observers).
    """

    def __init__(self, width_px: int, height_px: int, out_dir: str | Path, context: RunContext = RunContext()) -> None:
        config, detector = context.config, context.detector
        self.W, self.H, self.context = int(width_px), int(height_px), context
        self.config, self.detector = config, detector
        self.pitch = context.pitch
        self.graph_config = context.graph()
        self.curves = fitting_curves(self.pitch)
        self.sampling = TemplateSampling(self.pitch)
        self.confidence = context.confidence
        use_tripod_now = context.tripod if config.use_tripod else None
        self.solver: StreamingSolver = context.solver_factory(config, self.graph_config, self.W, self.H, self.pitch,
                                                              use_tripod_now)
        self.online_tripod = OnlineTripod(config, self.graph_config, self.pitch, context.tripod, context.tripods)
        registry = CameraRegistry(known={camera_id: t.T_w for camera_id, t in (context.tripods or {}).items()})
        self.chain = Chain(config, registry, self.online_tripod, self.solver)
        self.policy = ReinitPolicy(config, context.reinitialise, refine_guesses, context.confidence, registry,
                                   context.reinit_positions,
                                   model_reinit_for(config.reinit_model) if detector else None,
                                   court_reinit if config.court_reinit and context.reinit_positions is None else None,
                                   chain=self.chain)
        self.out_dir = Path(out_dir)
        self.writer = TrackWriter(self.out_dir, self.W, self.H, also_960x540=config.write_960x540,
                                  run_info={**(context.run_info or {}), "mode": config.mode, "config": asdict(config)})
        self.kept: dict[int, FrameObservations] = {}
        self._history: deque[Camera] = deque(maxlen=2)
        self._last_std: np.ndarray | None = None
        self.cuts = 0  # cuts that broke the chain
        self.faint_look_frames = 0  # frames whose markings took the faint look (a second look, a chain needing it)
        self.shot_index: int | None = None  # the current shot (None: no shot information)
        self.shot_camera_ids: dict[int, str] = {}  # shot index -> the camera id of its first confident frame
        self.backfill = None
        if context.backfill and detector is not None and hasattr(detector, "name") and config.recover_max_frames > 0:
            self.backfill = Backfill(detector.name, self.confidence, self.pitch, self.curves, self.sampling,
                                     self.graph_config, config.confidence_threshold, config.recover_max_frames,
                                     lambda camera_id: self.online_tripod.by_camera(self.solver).get(camera_id))
        # Seconds per stage in this thread; markings_ahead_s: the camera-free half of detection done ahead,
        # where the frames are decoded (overlapping the stages here; see track.ahead).
        self.timings = {"backfill_s": 0.0, "detect_s": 0.0, "flow_s": 0.0, "solve_s": 0.0, "confidence_s": 0.0, "reinit_s": 0.0,
                        "write_s": 0.0, "markings_ahead_s": 0.0}
        self.observer = FrameObserver(detector, config, self.W, self.H, self.pitch, context.mask_paths or {},
                                      self.timings)
        self._last_done: tuple[FrameObservations | None, Detections | None] = (None, None)  # the last frame solved
        self.records = RecordQueue(self.writer, lambda camera, observations, detections: self.confidence(
            camera, observations, detections, self.curves, self.sampling),
            None if self.backfill is None else self.backfill.final, self.timings)

    def process(self, frame: FrameInput) -> None:
        """Process one frame, write every record that became final, and tell the observer."""
        if self.backfill is not None:
            self.backfill.note(frame)
        if frame.repeats_previous and self.records.can_repeat():
            # The previous frame's image again: its estimate, once final, is this frame's; nothing is solved.
            self.records.repeat(frame)
            handed, detections = self._last_done
        else:
            handed, detections = self._last_done = self._process(frame)
        if self.context.on_frame_done is not None:
            self.context.on_frame_done(frame, handed, detections)

    def _process(self, frame: FrameInput) -> tuple[FrameObservations | None, Detections | None]:
        """Returns (the observations handed to the solver or None, the frame's detections or None)."""
        if not frame.has_image and frame.observations is None:
            # The camera barely moves over one lost frame: keep the track, drop only the flow link.
            self.records.emit_now(frame, FrameStatus.MISSING_FRAME, frame.problem or "frame could not be read")
            self.observer.unlink()
            return None, None
        shot = frame.shot
        if shot is not None:
            if shot.cut and shot.shot_index > 0:
                self._end_chain()  # nothing is linked across a cut
                self.cuts += 1
            if shot.cut or shot.shot_index != self.shot_index:
                self.chain.new_stretch()  # a new shot: its camera is not known yet ...
                self.policy.new_stretch()  # ... and searched at once
            self.shot_index = shot.shot_index
            if shot.is_other_view and self.chain.lost and not self.policy.looks_at_other_view(frame.frame_index):
                # Another view (close-up, crowd) with no chain, on a frame the court model does not look at.
                return self._other_view(frame)
        lost = self.chain.lost
        predicted = None if lost else predicted_camera(self._history, self._last_std, self.W)
        try:
            # A chain whose camera needed the faint look (detect.faint_lines) keeps it.
            self.faint_look_frames += self.chain.faint_look
            observations, detections = self.observer.observe(frame, predicted, None if lost or not self._history
                                                             else self._history[-1], self.chain.faint_look)
        except ValueError as exc:
            self.records.emit_now(frame, FrameStatus.FAILED, f"detector: {exc}")
            self._end_chain()
            return None, None
        if self.observer.shows_no_pitch(observations, detections):
            if frame.shows_other_view:
                return self._other_view(frame, detections)
            if detections is None and self._history and self.chain.carry():
                # A detections-file frame with (almost) nothing: carried on the motion prior, no camera claimed.
                return self._track(frame, observations, None, note=f"no detections; carried by the motion prior "
                                   f"({self.chain.carried} of at most {self.config.max_motion_prior_frames}); "
                                   "no camera")
            status = FrameStatus.NO_PITCH if detections is not None else FrameStatus.NO_DETECTIONS
            reason = "no pitch in view" if detections is not None else "no detections for this frame"
            self.records.emit_now(frame, status, reason)
            self._end_chain()
            return None, detections
        return self._track(frame, observations, detections)

    def _track(self, frame: FrameInput, observations: FrameObservations, detections: Detections | None,
               note: str | None = None) -> tuple[FrameObservations | None, Detections | None]:
        """Solve one frame with something to see; returns (observations handed to the solver or None, detections)."""
        reinitialised = False
        guess = None
        trust_previous = not self.chain.lost
        if self.chain.lost:
            # The court model may look again at the frame's markings with their faint look (detect.faint_lines).
            decision = self._decide(observations, detections, image=frame.image,
                                    faint_look=lambda: self.observer.faint_look(frame),
                                    other_view=frame.shows_other_view)
            if decision.faint_look:
                self.observer.take_faint_look(frame)  # the frame's markings are those its camera was found on
                self.faint_look_frames += 1
            if decision.camera is None and frame.shows_other_view:
                return self._other_view(frame, detections, decision.reason)
            if decision.camera is None:
                self.records.emit_now(frame, FrameStatus.UNPLACED if detections is not None else FrameStatus.NO_DETECTIONS,
                                      f"no camera found: {decision.reason}")
                self._end_chain()
                return None, detections
            self._start_chain(frame, observations, decision)
            guess, reinitialised = decision.camera, True
            if self.chain.place_known:
                self.solver.hold_position_next()  # a known camera's place: not moved by one frame's few markings
            observations, detections = self.observer.named_by(frame, observations, detections, guess)
        started = time.perf_counter()
        fallback = self._history[-1] if self._history else None
        current, released = self.solver.push(observations, guess, trust_previous, fallback)
        self.timings["solve_s"] += time.perf_counter() - started

        entry = PendingFrame(frame, FrameStatus.REINITIALISED if reinitialised else FrameStatus.TRACKED, note, reinitialised,
                             detections, observations)
        if note is not None:
            entry.status, entry.suppress_camera = FrameStatus.MOTION_PRIOR, True
        else:
            self.chain.observed()
        self.records.add(entry)
        if self.context.keep_observations:
            self.kept[frame.frame_index] = replace(observations, marking_mask=None)
        self._judge(entry, current, reinitialised, carried=note is not None)
        for estimate in released:
            self.records.resolve(estimate)
        self.records.flush()
        return observations, detections

    def _other_view(self, frame: FrameInput, detections: Detections | None = None, why: str | None = None
                    ) -> tuple[None, Detections | None]:
        """Record a frame the shot step reads as another view (close-up, crowd) that gets no camera (``why``: what the
        court model found on it); the chain ends. Returns (no observations handed, the frame's detections)."""
        shot = frame.shot
        self.records.emit_now(frame, FrameStatus.OTHER_VIEW, f"other view ({shot.kind}): {shot.reason}"
                              + (f"; {why}" if why else ""))
        self._end_chain()
        return None, detections

    def _decide(self, observations: FrameObservations, detections: Detections | None, held: Camera | None = None,
                held_confidence: float | None = None, image=None, faint_look=None,
                other_view: bool = False) -> ReinitDecision:
        """The re-initialisation policy's decision for this frame (its time counted; image: for the field model;
        faint_look: the frame's detections with their faint look, when asked; other_view: the shot step reads the
        frame as another view, the court model alone looks for a camera from nothing)."""
        started = time.perf_counter()
        decision = self.policy.decide(observations, detections, self.pitch, self.curves, self.sampling, held,
                                      held_confidence, image, faint_look, other_view)
        self.timings["reinit_s"] += time.perf_counter() - started
        if decision.camera is not None and not self.config.estimate_k1:
            decision = replace(decision, camera=decision.camera.replace(k1=0.0))
        return decision

    def _judge(self, entry: PendingFrame, current: FrameEstimate, reinitialised: bool, carried: bool) -> None:
        """Score the frame's camera and apply the judge's verdict (:func:`~broadtrack_graph.track.judge.judge`):
        re-initialise it when asked, then write it, hold it back, or end the chain."""
        observations, detections = entry.observations, entry.detections
        camera = current.camera
        confidence = None
        if camera is not None:
            started = time.perf_counter()
            confidence = self.confidence(camera, observations, detections, self.curves, self.sampling)
            self.timings["confidence_s"] += time.perf_counter() - started
        moved = None if camera is None or not self._history or reinitialised \
            else image_motion_px(self._history[-1], camera)  # from the chain's previous frame
        across = None  # read only in a fast sweep (the judge's rule 5)
        if moved is not None and moved > self.config.max_unsure_motion_px:
            across = frame_recall_across_motion(camera, self._history[-1], detections, self.curves)
        facts = FrameFacts(confidence, camera is not None, self.chain.trusted, self.chain.trust_at, reinitialised,
                           from_marking_map=detections is not None and detections.marking_mask is not None,
                           carried=carried, image_motion_px=moved, recall_across_motion=across,
                           place_held=self._place_held(confidence))
        verdict = judge(facts, self.config)
        replaced = False  # the solved camera was replaced by the decision's
        if verdict.action is Action.REINITIALISE and camera is not None and self.chain.trusted \
                and confidence is not None and confidence >= self.config.lost_confidence \
                and not self.policy.asks_about_held(entry.frame.frame_index):
            # A trusted chain's camera under the threshold, tried a frame or a few before: kept till the next try.
            verdict = judge(replace(facts, asked=True), self.config)
        if verdict.action is Action.REINITIALISE:
            # Re-initialise this frame; the next frame is linked to the camera it gets, not to the solved one.
            decision = self._decide(observations, detections, camera, confidence, entry.frame.image,
                                    other_view=entry.frame.shows_other_view)
            if decision.camera is not None:
                self._start_chain(entry.frame, observations, decision)
                self.solver.replace_last(decision.camera)
                entry.reinitialised, entry.status = True, FrameStatus.REINITIALISED
                entry.override_camera = decision.camera
                camera, confidence, replaced = decision.camera, decision.confidence, True
            verdict = judge(replace(facts, confidence=confidence, has_camera=camera is not None, asked=True,
                                    replaced=replaced, chain_trusted=self.chain.trusted,
                                    trust_at=self.chain.trust_at,
                                    image_motion_px=None if replaced else facts.image_motion_px,
                                    recall_across_motion=None if replaced else facts.recall_across_motion,
                                    place_held=self._place_held(confidence)), self.config)
        entry.confidence, entry.confidence_camera = confidence, camera
        if verdict.action is not Action.LOST and confidence is not None and not carried:
            self.chain.rated(confidence)
        if verdict.withholds_camera:
            entry.status, entry.reason, entry.suppress_camera = FrameStatus.FAILED, verdict.reason, True
            entry.override_camera = None
        if verdict.action is Action.LOST:
            self._end_chain()
        else:
            if replaced and not self.chain.continued:
                self._history.clear()  # a new chain: the replaced chain's motion is not its motion
            self._history.append(camera)
            self._last_std = current.std
            self.chain.goes_on()
            if verdict.trusted:
                self.chain.trust(entry.frame.frame_index)
            if verdict.confident:
                self.chain.identify_at(camera)
                self.policy.confident(entry.frame.frame_index, camera)
                if self.shot_index is not None:
                    self.shot_camera_ids.setdefault(self.shot_index, self.chain.camera_id)
        written = verdict.action is not Action.LOST and not entry.suppress_camera
        self.online_tripod.update(self.solver, camera if written else None, confidence)
        entry.camera_id = self.chain.camera_id
        tripod = self.chain.settled_tripod()
        if tripod is not None:
            self.policy.tripod(self.chain.camera_id, tripod.T_w)  # the fitted tripod identifies the camera

    def _place_held(self, confidence: float | None) -> bool:
        """A tripod holds the chain's focal point, or half its scored frames, this one at ``confidence`` counted, reach
        the tripod's bar (the judge's rule 7)."""
        return self.solver.tripod is not None or self.chain.mostly_sure(confidence)

    def _start_chain(self, frame: FrameInput, observations: FrameObservations, decision: ReinitDecision) -> None:
        """A decision's camera starts the chain; the chain keeps the faint look when the camera was found on the
        frame's faint look and, on the markings found without it, is under the bar its chain is trusted from."""
        self.chain.start(decision)
        before = self.observer.without_faint_look(frame)
        keeps = before is not None
        if keeps and before.marking_mask is not None and before.marking_mask.any():
            confidence = self.confidence(decision.camera, observations, before, self.curves, self.sampling)
            keeps = confidence is None or confidence < max(self.chain.trust_at, self.config.confidence_threshold)
        self.chain.faint_look = keeps

    def _end_chain(self) -> None:
        """The next frame is not linked to the previous one (no flow, re-initialise)."""
        self.chain.end()
        self.observer.unlink()
        self._history.clear()

    def finish(self, extra_summary: dict | None = None) -> RunResult:
        """Release the smoother's last frames, write the tripod and close the run."""
        for estimate in self.solver.finish():
            self.records.resolve(estimate)
        self.records.close_unreleased()
        if self.backfill is not None:
            self.backfill.finish()
            self.timings["backfill_s"] = self.backfill.seconds
        extra = dict(extra_summary or {})
        tripod, by_camera = self.online_tripod.write(self.solver, RunFolder(self.out_dir), extra)
        model_s = {"reinit_model_s": self.policy.tries.model.seconds} if self.policy.tries.model is not None else {}
        extra["timings_s"] = {k: round(v, 3) for k, v in {**self.timings, **model_s}.items()}
        extra["solver_restarts"] = self.solver.rebuilds
        extra["reinit_searches"] = dict(self.policy.counts)
        extra["cuts"] = self.cuts
        extra["faint_look_frames"] = self.faint_look_frames
        summary = self.writer.close(extra)
        return RunResult(self.out_dir, summary, None, tripod, by_camera)
