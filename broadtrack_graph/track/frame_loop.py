"""The per-frame state machine of a tracking run: predict, detect, solve, check confidence, re-initialise.

One loop serves every input: frames with a detector (weight-free or ONNX), a
detections file alone, or a detections file with frames (flow on). Per frame:

1. the detector finds the markings, named with the predicted camera (the previous
   estimate, extrapolated: :mod:`broadtrack_graph.track.prediction`), and optical flow
   links the frame to the previous one (only while the previous camera is trusted);
2. lost (first frame, after a cut or a failed frame): the front end re-initialises
   (keypoints, labelled lines, or a global search on the marking map, at the known
   tripod or at the default camera positions) and the solver is re-anchored;
3. the streaming solver (iSAM2 online, or the fixed-lag smoother) adds the frame;
4. the confidence (Jaccard index of the marking map and the projected template, or
   the agreement of labelled detections when there is no map) is checked: below the
   threshold the frame is re-initialised and the next frame does not trust flow
   from it;
Frames annotated by the shot step (:mod:`broadtrack_graph.track.shot_stream`): a cut
breaks the chain (no flow, no motion prior across it: the next frame is re-initialised);
a frame of another view (close-up, crowd) gets no camera and the status ``other-view``;
the static graphics mask is taken out of the detections (and so out of flow's keep mask).

5. each finished frame is written at once (camera file + a flushed track line), in
   frame order, so an interrupted run keeps every frame it finished.

Without a known tripod, the online modes fit one on the confident opening frames
(:mod:`broadtrack_graph.track.online_tripod`). Whole runs: :mod:`broadtrack_graph.track.passes`.
"""

from __future__ import annotations

import time
from collections import deque
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Callable

import numpy as np

from broadtrack_graph.detect.detector import Detections, PredictedCamera
from broadtrack_graph.detect.flow import grid_flow, prepare
from broadtrack_graph.detect.graphics import mask_graphics
from broadtrack_graph.detect.observations import FrameObservations
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves, TemplateSampling
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.estimates import FrameEstimate
from broadtrack_graph.graph.streaming import StreamingSolver
from broadtrack_graph.io.run_folder import RunFolder
from broadtrack_graph.io.track_record import (
    STATUS_FAILED,
    STATUS_MISSING_FRAME,
    STATUS_MOTION_PRIOR,
    STATUS_NO_DETECTIONS,
    STATUS_NO_PITCH,
    STATUS_OTHER_VIEW,
    STATUS_REINITIALISED,
    STATUS_TRACKED,
    STATUS_UNPLACED,
    TrackRecord,
)
from broadtrack_graph.io.track_writer import TrackWriter
from broadtrack_graph.reinit.cheap import refine_guesses
from broadtrack_graph.reinit.frame import frame_confidence, reinitialise
from broadtrack_graph.track.config import TrackingConfig, graph_config_for, streaming_solver_for
from broadtrack_graph.track.inputs import FrameInput, mask_file_detections
from broadtrack_graph.track.online_tripod import OnlineTripod
from broadtrack_graph.track.prediction import predicted_camera
from broadtrack_graph.track.recover import RECOVERABLE_STATUSES
from broadtrack_graph.shots.segmenter import MAIN_CAMERA_ID
from broadtrack_graph.track.backfill import Backfill
from broadtrack_graph.track.camera_ids import CameraRegistry
from broadtrack_graph.track.reinit_policy import ReinitDecision, ReinitPolicy
from broadtrack_graph.track.result import RunResult, std_fields

FrameDone = Callable[[FrameInput, FrameObservations | None, Detections | None], None]
"""Observer of a processed frame: (frame, what it handed the solver or None, its detections or None)."""


@dataclass
class _Pending:
    """A frame waiting for its estimate (fixed-lag) before its record can be written."""

    frame: FrameInput
    status: str
    reason: str | None = None
    reinitialised: bool = False
    detections: Detections | None = None
    observations: FrameObservations | None = None
    record: TrackRecord | None = None
    override_camera: Camera | None = None
    confidence: float | None = None  # of confidence_camera, computed when the frame was added
    suppress_camera: bool = False  # the frame's estimate is not trusted: write no camera
    confidence_camera: Camera | None = None
    camera_id: str | None = None  # the broadcast camera of the frame


class TrackingRun:
    """One tracking run over a stream of :class:`FrameInput` (see the module docstring).

    Args:
        width_px, height_px: input resolution.
        out_dir: run folder (cameras/, track.jsonl, summary.json, tripod.json).
        config: tracking options.
        detector: a FieldDetector for image input (None when every frame brings observations).
        tripod: a known tripod (e.g. from an earlier run), or None.
        pitch: the template.
        graph_config: solver sigmas (default from :func:`graph_config_for`).
        run_info: stored in summary.json.
        keep_observations: keep every frame's observations (needed by the batch pass).
        reinit_positions: candidate focal points (metres) for re-initialisation without a tripod.
        mask_paths: frame index -> marking-mask PNG named by a detections file.
        solver_factory: ``(config, graph_config, width_px, height_px, pitch, tripod) -> StreamingSolver``
            (default :func:`streaming_solver_for`).
        reinitialise: one global search, ``(observations, detections, pitch, positions, curves, sampling) ->
            ReinitResult`` (default :func:`broadtrack_graph.reinit.frame.reinitialise`); when and where it runs is
            decided by :class:`~broadtrack_graph.track.reinit_policy.ReinitPolicy`.
        confidence: ``(camera, observations, detections, curves, sampling) -> float | None``
            (default :func:`broadtrack_graph.reinit.frame.frame_confidence`).
        on_frame_done: observer called after every processed frame (:data:`FrameDone`).
        tripods: known tripods by camera id (e.g. "main"), used when that camera is found; ``tripod``
            is the main camera's.
        backfill: offline modes: frames left without a camera are walked in from their neighbours' cameras
            (:mod:`broadtrack_graph.track.backfill`; needs a detector that finds its markings ahead).
    """

    def __init__(self, width_px: int, height_px: int, out_dir: str | Path, config: TrackingConfig = TrackingConfig(),
                 detector=None, tripod: Tripod | None = None, pitch: PitchTemplate | None = None,
                 graph_config: GraphConfig | None = None, run_info: dict | None = None,
                 keep_observations: bool = False, reinit_positions=None, mask_paths: dict | None = None,
                 solver_factory=streaming_solver_for, reinitialise=reinitialise, confidence=frame_confidence,
                 on_frame_done: FrameDone | None = None, tripods: dict[str, Tripod] | None = None,
                 backfill: bool = False) -> None:
        self.W, self.H = int(width_px), int(height_px)
        self.config = config
        self.detector = detector
        self.pitch = pitch or PitchTemplate()
        self.graph_config = graph_config or graph_config_for(config)
        self.curves = TemplateCurves(self.pitch, line_step_m=1.0, circle_step_m=0.5)
        self.sampling = TemplateSampling(self.pitch)
        self.known_tripod = tripod
        self.mask_paths = mask_paths or {}
        known = {camera_id: t.T_w for camera_id, t in (tripods or {}).items()}
        self.policy = ReinitPolicy(config, reinitialise, refine_guesses, confidence, CameraRegistry(known=known),
                                   search_positions=reinit_positions)
        self.confidence = confidence
        self.on_frame_done = on_frame_done
        use_tripod_now = tripod if (config.use_tripod and tripod is not None) else None
        self.solver: StreamingSolver = solver_factory(config, self.graph_config, self.W, self.H, self.pitch,
                                                      use_tripod_now)
        self.online_tripod = OnlineTripod(config, self.graph_config, self.pitch, tripod, tripods)
        self.out_dir = Path(out_dir)
        self.writer = TrackWriter(self.out_dir, self.W, self.H, also_960x540=config.write_960x540,
                                  run_info={**(run_info or {}), "mode": config.mode, "config": asdict(config)})
        self.keep_observations = keep_observations
        self.kept: dict[int, FrameObservations] = {}
        self._pending: deque[_Pending] = deque()
        self._history: deque[Camera] = deque(maxlen=2)
        self._last_std: np.ndarray | None = None
        self._lost = True
        self._carried = 0  # frames in a row carried on the motion prior alone
        self._chain_confident = False  # a frame of the current chain reached the confidence threshold
        self._reinit_continues = False
        self._prev_grey: np.ndarray | None = None
        self._prev_keep_mask: np.ndarray | None = None
        self.cuts = 0  # cuts that broke the chain
        self.camera_id: str | None = None  # the camera id of the current chain (None: not known yet)
        self.shot_index: int | None = None  # the current shot (None: no shot information)
        self.shot_camera_ids: dict[int, str] = {}  # shot index -> the camera id of its first confident frame
        # Seconds per stage in this thread; markings_ahead_s: the camera-free half of detection done ahead,
        # in the thread that decodes the frames (overlapping the stages here; see track.passes.run_loop).
        self.backfill = None
        if backfill and detector is not None and hasattr(detector, "name") and config.recover_max_frames > 0:
            self.backfill = Backfill(detector.name, confidence, self.pitch, self.curves, self.sampling,
                                     self.graph_config, config.confidence_threshold, config.recover_max_frames,
                                     lambda camera_id: self.online_tripod.by_camera(self.solver).get(camera_id))
        self._ahead: dict[int, tuple[object | None, bool]] = {}  # frame -> (markings found ahead, shot cut before it)
        self.timings = {"backfill_s": 0.0, "detect_s": 0.0, "flow_s": 0.0, "solve_s": 0.0, "confidence_s": 0.0, "reinit_s": 0.0,
                        "write_s": 0.0, "markings_ahead_s": 0.0}

    # ----------------------------------------------------------------- one frame

    def process(self, frame: FrameInput) -> None:
        """Process one frame, write every record that became final, and tell the observer."""
        if self.backfill is not None:
            cut = frame.shot is not None and (frame.shot.cut or frame.shot.is_other_view)
            self._ahead[frame.frame_index] = (frame.markings, cut)
        handed, detections = self._process(frame)
        if self.on_frame_done is not None:
            self.on_frame_done(frame, handed, detections)

    def _process(self, frame: FrameInput) -> tuple[FrameObservations | None, Detections | None]:
        """Returns (the observations handed to the solver or None, the frame's detections or None)."""
        if frame.image is None and frame.observations is None:
            # The camera barely moves over one lost frame: keep the track, drop only the flow link.
            self._emit_now(frame, STATUS_MISSING_FRAME, frame.problem or "frame could not be read")
            self._prev_grey = None
            return None, None
        shot = frame.shot
        if shot is not None:
            if shot.cut and shot.shot_index > 0:
                self._break_chain()  # nothing is linked across a cut
                self.cuts += 1
            if shot.cut or shot.shot_index != self.shot_index:
                self.policy.new_stretch()  # a new shot: its camera is not known yet, searched at once
                self.camera_id = None
            self.shot_index = shot.shot_index
            if shot.is_other_view:
                self._emit_now(frame, STATUS_OTHER_VIEW, f"other view ({shot.kind}): {shot.reason}")
                self._break_chain()
                return None, None
        detections = None
        grey = None
        observations = frame.observations
        if frame.image is not None:
            if observations is None:
                started = time.perf_counter()
                predicted = None if self._lost else predicted_camera(self._history, self._last_std, self.W)
                try:
                    detections = self._detect(frame, predicted)
                except ValueError as exc:
                    self._emit_now(frame, STATUS_FAILED, f"detector: {exc}")
                    self._break_chain()
                    return None, None
                self.timings["detect_s"] += time.perf_counter() - started
                if frame.markings is not None:
                    self.timings["markings_ahead_s"] += frame.markings.seconds
            started = time.perf_counter()
            if self.config.use_flow:
                grey = frame.flow_frame if frame.flow_frame is not None else prepare(frame.image, self.config.flow)
            self.timings["flow_s"] += time.perf_counter() - started
        if detections is None and frame.frame_index in self.mask_paths and observations is not None:
            detections = mask_file_detections(self.mask_paths[frame.frame_index], observations, self.W, self.H)
        flow = None
        if grey is not None and self._prev_grey is not None and not self._lost and self._history:
            started = time.perf_counter()
            flow = grid_flow(self._prev_grey, grey, self.W, self.H, self._history[-1], self._prev_keep_mask,
                             self.config.flow, (self.pitch.dimensions.length_m / 2, self.pitch.dimensions.width_m / 2))
            self.timings["flow_s"] += time.perf_counter() - started
        if detections is not None and frame.observations is None:
            observations = detections.to_observations(frame.frame_index, flow)
            keep = detections.field_mask
            if keep is not None and detections.player_mask is not None:
                keep = keep & ~detections.player_mask
            self._prev_keep_mask = keep
        elif flow is not None:
            observations = replace(observations, flow=flow)
        self._prev_grey = grey
        if observations.width_px != self.W or observations.height_px != self.H:
            observations = observations.rescaled(self.W, self.H)

        if self._no_pitch(observations, detections):
            if detections is None and not self._lost and self._history \
                    and self._carried < self.config.max_motion_prior_frames:
                # A detections-file frame with (almost) nothing: carried on the motion prior, no camera claimed.
                self._carried += 1
                return self._track(frame, observations, None, note=f"no detections; carried by the motion prior "
                                   f"({self._carried} of at most {self.config.max_motion_prior_frames}); no camera")
            status = STATUS_NO_PITCH if detections is not None else STATUS_NO_DETECTIONS
            reason = "no pitch in view" if detections is not None else "no detections for this frame"
            self._emit_now(frame, status, reason)
            self._break_chain()
            return None, detections
        return self._track(frame, observations, detections)

    def _detect(self, frame: FrameInput, predicted: PredictedCamera | None) -> Detections:
        """The frame's detections without what lies under graphics; from the markings found ahead when there."""
        if frame.markings is not None:
            detections = self.detector.name(frame.markings, predicted)
        else:
            detections = self.detector.detect(frame.image, predicted)
        return mask_graphics(detections, frame.graphics_mask)

    def _no_pitch(self, observations: FrameObservations, detections: Detections | None) -> bool:
        if detections is not None:
            grass = detections.field_mask.mean() if detections.field_mask is not None else 1.0
            points = len(detections.marking_points_px) + sum(len(p) for p in detections.lines_px.values())
            return grass < self.config.min_grass_share or points < self.config.min_marking_points
        return observations.is_empty or (observations.line_point_count < 4 and not observations.keypoints)

    def _track(self, frame: FrameInput, observations: FrameObservations, detections: Detections | None,
               note: str | None = None) -> tuple[FrameObservations | None, Detections | None]:
        """Solve one frame with something to see; returns (observations handed to the solver or None, detections)."""
        reinitialised = False
        guess = None
        trust_previous = not self._lost
        self._reinit_continues = False  # the frame's re-initialisation continues a confident camera's chain
        if self._lost:
            decision = self._decide(observations, detections)
            if decision.camera is None:
                self._emit_now(frame, STATUS_UNPLACED if detections is not None else STATUS_NO_DETECTIONS,
                               f"no camera found: {decision.reason}")
                self._break_chain()
                return None, detections
            self._adopt(decision)
            guess, self._reinit_continues = decision.camera, decision.continues_chain
            reinitialised = True
            observations = replace(observations, flow=None)
            if (self.detector is not None and frame.image is not None and detections is not None
                    and detections.marking_mask is not None and not observations.lines_px):
                # Name the markings with the re-initialised camera so the first frame has line factors.
                redetected = self._detect(frame, PredictedCamera(guess, 3.0))
                observations = redetected.to_observations(frame.frame_index, None)
                detections = redetected
        started = time.perf_counter()
        fallback = self._history[-1] if self._history else None
        current, released = self.solver.push(observations, guess, trust_previous, fallback)
        self.timings["solve_s"] += time.perf_counter() - started

        entry = _Pending(frame, STATUS_REINITIALISED if reinitialised else STATUS_TRACKED, note, reinitialised,
                         detections, observations)
        if note is not None:
            entry.status, entry.suppress_camera = STATUS_MOTION_PRIOR, True
        else:
            self._carried = 0
        self._pending.append(entry)
        if self.keep_observations:
            self.kept[frame.frame_index] = replace(observations, marking_mask=None)
        self._check_confidence(entry, current, reinitialised)
        for estimate in released:
            self._resolve(estimate)
        self._flush()
        return observations, detections

    def _decide(self, observations: FrameObservations, detections: Detections | None, held: Camera | None = None,
                held_confidence: float | None = None) -> ReinitDecision:
        """The re-initialisation policy's decision for this frame (its time counted)."""
        started = time.perf_counter()
        decision = self.policy.decide(observations, detections, self.pitch, self.curves, self.sampling, held,
                                      held_confidence, self._chain_confident)
        self.timings["reinit_s"] += time.perf_counter() - started
        if decision.camera is not None and not self.config.estimate_k1:
            decision = replace(decision, camera=decision.camera.replace(k1=0.0))
        return decision

    def _adopt(self, decision: ReinitDecision) -> None:
        """Restarting from the decision's camera: its camera id (and that camera's tripod) from now on."""
        if decision.camera_id is not None and decision.camera_id != self.camera_id:
            self._set_camera(decision.camera_id)

    def _set_camera(self, camera_id: str) -> None:
        self.online_tripod.switch(self.solver, camera_id)
        self.policy.switch(camera_id)
        self.camera_id = camera_id

    def _check_confidence(self, entry: _Pending, current: FrameEstimate, reinitialised: bool) -> None:
        """Score the frame's camera; re-initialise it when low; mark it lost or extend the chain."""
        observations, detections = entry.observations, entry.detections
        camera = current.camera
        confidence = None
        if camera is not None:
            started = time.perf_counter()
            confidence = self.confidence(camera, observations, detections, self.curves, self.sampling)
            self.timings["confidence_s"] += time.perf_counter() - started
        low = confidence is not None and confidence < self.config.confidence_threshold
        lost_now = reinitialised and confidence is not None and confidence < self.config.lost_confidence
        continues_chain = reinitialised and self._reinit_continues
        if camera is None or (low and not reinitialised):
            # Re-initialise this frame; the next frame does not trust flow from the previous camera.
            decision = self._decide(observations, detections, camera, confidence)
            if decision.camera is not None:
                self._adopt(decision)
                self.solver.reset(decision.camera)
                entry.reinitialised = True
                entry.status = STATUS_REINITIALISED
                entry.override_camera = decision.camera
                camera, confidence = decision.camera, decision.confidence
                continues_chain = decision.continues_chain
            elif camera is None or (confidence or 0.0) < self.config.lost_confidence:
                lost_now = True
        entry.confidence, entry.confidence_camera = confidence, camera
        if entry.reinitialised and not continues_chain:
            # A new chain starts at this frame (a refined guess, a confident camera moved onto this
            # frame, continues the chain it came from).
            self._chain_confident = False
        if confidence is not None and confidence >= self.config.confidence_threshold:
            self._chain_confident = True
        elif (not lost_now and camera is not None and confidence is not None and not self._chain_confident
              and detections is not None and detections.marking_mask is not None):
            # A chain started from the unlabelled marking map without one confident frame since: the camera
            # seeds the next frame, it is not written (a map search can settle on a wrong camera that still
            # explains part of the map; labelled lines and keypoints name what they show).
            entry.status = STATUS_FAILED
            entry.reason = (f"confidence {confidence:.2f} below {self.config.confidence_threshold:.2f} and no "
                            "confident frame since the re-initialisation; camera not written")
            entry.suppress_camera = True
        if lost_now and camera is not None and confidence is not None:
            entry.status = STATUS_FAILED
            entry.reason = f"confidence {confidence:.2f} below {self.config.lost_confidence:.2f} and re-initialisation failed"
            entry.override_camera = None
            entry.suppress_camera = True
        if lost_now or camera is None:
            self._break_chain()
        else:
            self._history.append(camera)
            self._last_std = current.std
            self._lost = False
            if confidence is not None and confidence >= self.config.confidence_threshold and not entry.suppress_camera:
                if self.camera_id is None:
                    self._set_camera(self.policy.registry.identify(camera.position_m))
                self.policy.confident(entry.frame.frame_index, camera)
                if self.shot_index is not None:
                    self.shot_camera_ids.setdefault(self.shot_index, self.camera_id)
        self.online_tripod.update(self.solver, None if (lost_now or entry.suppress_camera) else camera, confidence)
        entry.camera_id = self.camera_id
        if self.camera_id is not None and self.solver.tripod is not None and not self.online_tripod.provisional:
            self.policy.tripod(self.camera_id, self.solver.tripod.T_w)  # the fitted tripod identifies the camera

    # ----------------------------------------------------------------- records

    def _resolve(self, estimate: FrameEstimate) -> None:
        """Build the record of the pending frame this released estimate belongs to."""
        for entry in self._pending:
            if entry.frame.frame_index == estimate.frame_index and entry.record is None:
                camera = None if entry.suppress_camera else (entry.override_camera or estimate.camera)
                status = entry.status if (camera is not None or entry.status == STATUS_MOTION_PRIOR) else STATUS_FAILED
                reason = entry.reason if (camera is not None or entry.suppress_camera) else (estimate.reason or "solver failed")
                confidence = None
                if camera is not None and entry.confidence_camera is not None and \
                        np.allclose(camera.to_vector(), entry.confidence_camera.to_vector(), rtol=0, atol=1e-9):
                    confidence = entry.confidence  # online: the camera scored when the frame was added
                elif camera is not None:
                    confidence = self.confidence(camera, entry.observations, entry.detections, self.curves,
                                                 self.sampling)
                active = tuple(sorted(k for k, v in (estimate.active_factors or {}).items() if v))
                entry.record = TrackRecord(entry.frame.frame_index, entry.frame.frame_id, entry.frame.time_s, camera,
                                           std_fields(estimate) if camera is not None else {}, confidence,
                                           entry.reinitialised, status, reason, active,
                                           entry.camera_id if camera is not None else None)
                entry.detections = None
                return

    def _emit_now(self, frame: FrameInput, status: str, reason: str) -> None:
        """A frame without an estimate: its record is final now (written after the frames before it)."""
        entry = _Pending(frame, status, reason)
        entry.record = TrackRecord(frame.frame_index, frame.frame_id, frame.time_s, None, {}, None, False, status, reason)
        self._pending.append(entry)
        self._flush()

    def _break_chain(self) -> None:
        """The next frame is not linked to the previous one (no flow, re-initialise)."""
        self._lost = True
        self._prev_grey = None
        self._history.clear()
        self._carried = 0
        self._chain_confident = False

    def _flush(self) -> None:
        """Write the final records at the head of the queue (frame order)."""
        started = time.perf_counter()
        while self._pending and self._pending[0].record is not None:
            record = self._pending.popleft().record
            self.writer.write(record)  # records are read back from the file (RunResult.records)
            if self.backfill is not None:
                self._to_backfill(record)
        self.timings["write_s"] += time.perf_counter() - started

    def _to_backfill(self, record: TrackRecord) -> None:
        """Hand a final record to the back-fill (its time counted apart from writing)."""
        started = time.perf_counter()
        found, cut = self._ahead.pop(record.frame_index, (None, False))
        if cut:
            self.backfill.cut()
        if record.camera is not None:
            self.backfill.with_camera(record.frame_index, record.camera, record.camera_id)
        elif record.status in RECOVERABLE_STATUSES or record.status == STATUS_MISSING_FRAME:
            self.backfill.without_camera(record.frame_index, found)
        else:
            self.backfill.cut()  # another view: nothing is walked across it
        self.timings["backfill_s"] += time.perf_counter() - started
        self.timings["write_s"] -= time.perf_counter() - started

    def finish(self, extra_summary: dict | None = None) -> RunResult:
        """Release the smoother's last frames, write the tripod and close the run."""
        for estimate in self.solver.finish():
            self._resolve(estimate)
        for entry in self._pending:
            if entry.record is None:
                entry.record = TrackRecord(entry.frame.frame_index, entry.frame.frame_id, entry.frame.time_s, None, {},
                                           None, False, STATUS_FAILED, "no estimate released")
        self._flush()
        if self.backfill is not None:
            started = time.perf_counter()
            self.backfill.cut()
            self.timings["backfill_s"] += time.perf_counter() - started
        by_camera = self.online_tripod.by_camera(self.solver)
        tripod = by_camera.get(MAIN_CAMERA_ID, self.solver.tripod)  # the main camera's, else the last camera's
        extra = dict(extra_summary or {})
        fit_info = self.online_tripod.info
        if tripod is not None:
            extra["tripod"] = {"T_w": list(map(float, tripod.T_w)), "delta_m": float(tripod.delta_m)}
            RunFolder(self.out_dir).write_tripod(tripod, fit_info, by_camera)
        if fit_info:
            extra["tripod_fit"] = fit_info
        extra["timings_s"] = {k: round(v, 3) for k, v in self.timings.items()}
        extra["solver_restarts"] = self.solver.rebuilds
        extra["reinit_searches"] = dict(self.policy.counts)
        extra["cuts"] = self.cuts
        summary = self.writer.close(extra)
        return RunResult(self.out_dir, summary, None, tripod, by_camera)
