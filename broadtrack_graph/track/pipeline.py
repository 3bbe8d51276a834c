"""The tracking pipeline: frames -> detections -> factors -> solver -> track -> files.

One loop serves every input: frames with a detector (weight-free or ONNX), a
detections file alone, or a detections file with frames (flow on). Per frame:

1. the detector finds the markings, named with the predicted camera (the previous
   estimate, extrapolated), and optical flow links the frame to the previous one
   (only while the previous camera is trusted);
2. lost (first frame, after a cut or a failed frame): the front end re-initialises
   (keypoints, labelled lines, or a global search on the marking map, at the known
   tripod or at the default camera positions) and the solver is re-anchored;
3. the solver (iSAM2 online, or the fixed-lag smoother) adds the frame;
4. the confidence (Jaccard index of the marking map and the projected template, or
   the agreement of labelled detections when there is no map) is checked: below the
   threshold the frame is re-initialised and the next frame does not trust flow
   from it;
5. each finished frame is written at once (camera file + a flushed track line), so
   an interrupted run keeps every frame it finished.

Without a known tripod, the online modes track the opening frames without the
tripod term, fit (T, delta) to them (robust to outlier frames) and then hold it
fixed in the tripod factor; the offline mode does the paper's two passes: track
without the tripod term, fit, then a batch refinement (Levenberg-Marquardt over
overlapping chunks) that re-estimates the tripod with the trajectory. The fitted
tripod is written to ``tripod.json`` for later runs of the same camera.
"""

from __future__ import annotations

import logging
import math
import time
from collections import deque
from dataclasses import asdict, dataclass, replace
from pathlib import Path

import numpy as np
from tqdm import tqdm

from broadtrack_graph.detect.detector import Detections, PredictedCamera
from broadtrack_graph.detect.flow import grid_flow, prepare
from broadtrack_graph.detect.observations import FrameObservations
from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.batch import BatchRefiner
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.estimates import FrameEstimate, Track
from broadtrack_graph.graph.fixed_lag import FixedLagSmoother
from broadtrack_graph.graph.online import OnlineTracker
from broadtrack_graph.graph.tripod_fit import fit_tripod_for_run, provisional_tripod
from broadtrack_graph.io.detections import read_mask_png
from broadtrack_graph.io.prefetch import prefetch
from broadtrack_graph.io.track_record import (
    STATUS_FAILED,
    STATUS_MISSING_FRAME,
    STATUS_NO_DETECTIONS,
    STATUS_NO_PITCH,
    STATUS_REINITIALISED,
    STATUS_TRACKED,
    TrackRecord,
)
from broadtrack_graph.io.track_writer import TrackWriter
from broadtrack_graph.io.tripod_file import TRIPOD_FILE, write_tripod
from broadtrack_graph.metrics.soccernet import TemplateSampling
from broadtrack_graph.reinit.frame import frame_confidence, plausible_position, reinitialise
from broadtrack_graph.reinit.linefit import TemplateCurves
from broadtrack_graph.track.config import TrackingConfig, graph_config_for
from broadtrack_graph.track.inputs import FrameInput

log = logging.getLogger(__name__)


# --------------------------------------------------------------------------- front end per frame


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


def _std_record(estimate: FrameEstimate) -> dict:
    if estimate.std is None:
        return {}
    s = np.asarray(estimate.std, float)
    return {"focal_std_px": float(s[0]), "k1_std": float(s[1]), "pan_std_deg": math.degrees(s[2]),
            "tilt_std_deg": math.degrees(s[3]), "roll_std_deg": math.degrees(s[4]), "position_std_m": s[5:8].copy()}


def _predicted(history: deque, std: np.ndarray | None, width_px: int) -> PredictedCamera | None:
    """The previous camera moved by the last inter-frame motion, with a pixel uncertainty."""
    if not history:
        return None
    last = history[-1]
    state = last.to_vector()
    motion_px = 0.0
    if len(history) >= 2:
        velocity = state - history[-2].to_vector()
        velocity[1] = 0.0
        velocity[5:] = 0.0
        state = state + velocity
        motion_px = abs(velocity[2]) * state[0] + abs(velocity[3]) * state[0] + abs(velocity[0]) * 0.5
    uncertainty = 3.0 + 0.5 * motion_px
    if std is not None and np.all(np.isfinite(std)):
        uncertainty += math.hypot(std[2] * state[0], std[3] * state[0]) + 0.5 * std[0] / max(state[0], 1.0) * width_px
    try:
        camera = Camera.from_vector(state, last.width_px, last.height_px)
    except ValueError:
        camera = last
    return PredictedCamera(camera, float(min(uncertainty, 60.0)))


SOLVER_ERRORS = (RuntimeError, IndexError, ValueError)
"""What GTSAM raises on an ill-posed update or a key already marginalised (the solver is then rebuilt)."""


class _Solver:
    """Online or fixed-lag solver behind one interface: push a frame, get finished estimates.

    When GTSAM rejects an update (an indeterminate system after a bad re-initialisation),
    the solver is rebuilt and the frame is added again as a fresh start; frames still
    waiting in the old fixed-lag window are released as they were or reported failed.
    """

    def __init__(self, config: TrackingConfig, graph: GraphConfig, width_px: int, height_px: int,
                 pitch: PitchTemplate, tripod: Tripod | None) -> None:
        self._args = (config, graph, width_px, height_px, pitch)
        self.lagged = config.mode == "fixed-lag"
        self.rebuilds = 0
        self._build(tripod)

    def _build(self, tripod: Tripod | None) -> None:
        config, graph, width_px, height_px, pitch = self._args
        if self.lagged:
            self.smoother = FixedLagSmoother(width_px, height_px, pitch, graph, tripod, lag=config.lag_frames)
            self.tracker = self.smoother.tracker
        else:
            self.smoother = None
            self.tracker = OnlineTracker(width_px, height_px, pitch, graph, tripod)

    @property
    def tripod(self) -> Tripod | None:
        return self.tracker.tripod

    @tripod.setter
    def tripod(self, tripod: Tripod | None) -> None:
        self.tracker.tripod = tripod

    def push(self, observations: FrameObservations, guess: Camera | None, trust_previous: bool,
             fallback: Camera | None = None):
        """Returns (current filtered estimate, estimates released now).

        Args:
            fallback: camera to restart from if the solver fails (default: guess).
        """
        try:
            return self._push(observations, guess, trust_previous)
        except SOLVER_ERRORS as exc:
            start = guess or fallback
            log.warning("frame %d: solver update failed (%s); restarting the solver",
                        observations.frame_index, str(exc).strip().splitlines()[0] if str(exc).strip() else "error")
            released = []
            if self.lagged:
                try:
                    released = self.smoother.finish()
                except SOLVER_ERRORS:
                    released = []
            self._build(self.tripod)
            self.rebuilds += 1
            if start is None:
                failed = FrameEstimate(observations.frame_index, None, reason="solver failed and no camera to restart from")
                return failed, released + [failed]
            try:
                current, more = self._push(replace(observations, flow=None), start, False)
            except SOLVER_ERRORS:
                self._build(self.tripod)
                failed = FrameEstimate(observations.frame_index, None, reason="solver failed twice on this frame")
                return failed, released + [failed]
            return current, released + more

    def _push(self, observations: FrameObservations, guess: Camera | None, trust_previous: bool):
        if self.lagged:
            released = self.smoother.add_frame(observations, guess, trust_previous)
            current = self.tracker.estimate(self.tracker.last_step, observations.frame_index)
            return current, released
        current = self.tracker.add_frame(observations, guess, trust_previous)
        return current, [current]

    def reset(self, camera: Camera) -> None:
        self.tracker.reset(camera)

    def finish(self) -> list[FrameEstimate]:
        return self.smoother.finish() if self.lagged else []


# --------------------------------------------------------------------------- the loop


@dataclass
class RunResult:
    """What a run produced: its folder, summary, the per-frame records and the tripod used.

    ``records`` are read back from the run's ``track.jsonl`` on first use when the run did not
    keep them in memory (a long run does not: a record is about 1.5 KB, 200 MB over a match).
    """

    out_dir: Path
    summary: dict
    kept_records: list[TrackRecord] | None = None
    tripod: Tripod | None = None

    @property
    def records(self) -> list[TrackRecord]:
        if self.kept_records is None:
            from broadtrack_graph.io.run_folder import read_track

            self.kept_records = read_track(self.out_dir).records
        return self.kept_records


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
    """

    def __init__(self, width_px: int, height_px: int, out_dir: str | Path, config: TrackingConfig = TrackingConfig(),
                 detector=None, tripod: Tripod | None = None, pitch: PitchTemplate | None = None,
                 graph_config: GraphConfig | None = None, run_info: dict | None = None,
                 keep_observations: bool = False, reinit_positions=None, mask_paths: dict | None = None) -> None:
        self.W, self.H = int(width_px), int(height_px)
        self.config = config
        self.detector = detector
        self.pitch = pitch or PitchTemplate()
        self.graph_config = graph_config or graph_config_for(config)
        self.curves = TemplateCurves(self.pitch, line_step_m=1.0, circle_step_m=0.5)
        self.sampling = TemplateSampling(self.pitch)
        self.known_tripod = tripod
        self.reinit_positions = reinit_positions
        self.mask_paths = mask_paths or {}
        use_tripod_now = tripod if (config.use_tripod and tripod is not None) else None
        self.solver = _Solver(config if config.mode != "batch" else replace(config, mode="online"),
                              self.graph_config, self.W, self.H, self.pitch, use_tripod_now)
        self.out_dir = Path(out_dir)
        self.writer = TrackWriter(self.out_dir, self.W, self.H, also_960x540=config.write_960x540,
                                  run_info={**(run_info or {}), "mode": config.mode, "config": asdict(config)})
        self.keep_observations = keep_observations
        self.kept: dict[int, FrameObservations] = {}
        self._pending: deque[_Pending] = deque()
        self._history: deque[Camera] = deque(maxlen=2)
        self._last_std: np.ndarray | None = None
        self._lost = True
        self._prev_grey: np.ndarray | None = None
        self._prev_keep_mask: np.ndarray | None = None
        self._opening_cameras: list[Camera] = []
        self._provisional_tripod = False  # the solver's tripod is the provisional one (replaced by the fit)
        self.tripod_fit_info: dict | None = None
        self.timings = {"detect_s": 0.0, "flow_s": 0.0, "solve_s": 0.0, "confidence_s": 0.0, "reinit_s": 0.0,
                        "write_s": 0.0}

    # ----------------------------------------------------------------- positions for re-initialisation

    def _positions(self):
        tripod = self.solver.tripod or self.known_tripod
        if tripod is not None:
            return [tuple(tripod.T_w)]
        return self.reinit_positions

    # ----------------------------------------------------------------- one frame

    def process(self, frame: FrameInput) -> None:
        """Process one frame and write every record that became final."""
        if frame.image is None and frame.observations is None:
            # The camera barely moves over one lost frame: keep the track, drop only the flow link.
            self._emit_now(frame, STATUS_MISSING_FRAME, frame.problem or "frame could not be read")
            self._prev_grey = None
            return
        detections = None
        grey = None
        observations = frame.observations
        if frame.image is not None:
            if observations is None:
                started = time.perf_counter()
                predicted = None if self._lost else _predicted(self._history, self._last_std, self.W)
                try:
                    detections = self.detector.detect(frame.image, predicted)
                except ValueError as exc:
                    self._emit_now(frame, STATUS_FAILED, f"detector: {exc}")
                    self._break_chain()
                    return
                self.timings["detect_s"] += time.perf_counter() - started
            started = time.perf_counter()
            if self.config.use_flow:
                grey = frame.flow_frame if frame.flow_frame is not None else prepare(frame.image, self.config.flow)
            self.timings["flow_s"] += time.perf_counter() - started
        if detections is None and frame.frame_index in self.mask_paths and observations is not None:
            detections = self._file_mask_detections(frame.frame_index, observations)
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
            if detections is None and not self._lost and self._history:
                # A detections-file frame with (almost) nothing: tracked through on the motion prior.
                self._track(frame, observations, None, note="no detections; carried by the motion prior")
                return
            status = STATUS_NO_PITCH if detections is not None else STATUS_NO_DETECTIONS
            reason = "no pitch in view" if detections is not None else "no detections for this frame"
            self._emit_now(frame, status, reason)
            self._break_chain()
            return
        self._track(frame, observations, detections)

    def _file_mask_detections(self, frame_index: int, observations: FrameObservations) -> Detections | None:
        """A marking mask named by a detections file, as detections (for confidence and re-initialisation)."""
        masks = read_mask_png(self.mask_paths[frame_index], self.W, self.H)
        if masks is None:
            return None
        mask, field = masks
        ys, xs = np.nonzero(mask)
        keep = slice(None, None, max(1, len(xs) // 2000))
        return Detections(self.W, self.H, lines_px=dict(observations.lines_px),
                          marking_points_px=np.column_stack([xs[keep], ys[keep]]).astype(float),
                          keypoints=observations.keypoints, marking_mask=mask, field_mask=field)

    def _no_pitch(self, observations: FrameObservations, detections: Detections | None) -> bool:
        if detections is not None:
            grass = detections.field_mask.mean() if detections.field_mask is not None else 1.0
            points = len(detections.marking_points_px) + sum(len(p) for p in detections.lines_px.values())
            return grass < self.config.min_grass_share or points < self.config.min_marking_points
        return observations.is_empty or (observations.line_point_count < 4 and not observations.keypoints)

    def _track(self, frame: FrameInput, observations: FrameObservations, detections: Detections | None,
               note: str | None = None) -> None:
        reinitialised = False
        guess = None
        trust_previous = not self._lost
        if self._lost:
            started = time.perf_counter()
            result = reinitialise(observations, detections, self.pitch, self._positions(), self.curves, self.sampling)
            self.timings["reinit_s"] += time.perf_counter() - started
            if result.camera is None:
                self._emit_now(frame, STATUS_NO_PITCH if detections is not None else STATUS_NO_DETECTIONS,
                               f"re-initialisation failed: {result.reason}")
                self._break_chain()
                return
            guess = result.camera if self.config.estimate_k1 else result.camera.replace(k1=0.0)
            reinitialised = True
            observations = replace(observations, flow=None)
            if (self.detector is not None and frame.image is not None and detections is not None
                    and detections.marking_mask is not None and not observations.lines_px):
                # Name the markings with the re-initialised camera so the first frame has line factors.
                redetected = self.detector.detect(frame.image, PredictedCamera(guess, 3.0))
                observations = redetected.to_observations(frame.frame_index, None)
                detections = redetected
        started = time.perf_counter()
        fallback = self._history[-1] if self._history else None
        self.on_solver_input(frame, observations, detections)
        current, released = self.solver.push(observations, guess, trust_previous, fallback)
        self.timings["solve_s"] += time.perf_counter() - started

        entry = _Pending(frame, STATUS_REINITIALISED if reinitialised else STATUS_TRACKED, note, reinitialised,
                         detections, observations)
        self._pending.append(entry)
        if self.keep_observations:
            self.kept[frame.frame_index] = replace(observations, marking_mask=None)

        camera = current.camera
        confidence = None
        if camera is not None:
            started = time.perf_counter()
            confidence = frame_confidence(camera, observations, detections, self.curves, self.sampling)
            self.timings["confidence_s"] += time.perf_counter() - started
        low = confidence is not None and confidence < self.config.confidence_threshold
        lost_now = reinitialised and confidence is not None and confidence < self.config.lost_confidence
        if camera is None or (low and not reinitialised):
            # Re-initialise this frame; the next frame does not trust flow from the previous camera.
            started = time.perf_counter()
            result = reinitialise(observations, detections, self.pitch, self._positions(), self.curves, self.sampling)
            self.timings["reinit_s"] += time.perf_counter() - started
            new_confidence = None
            if result.camera is not None:
                new_confidence = frame_confidence(result.camera, observations, detections, self.curves, self.sampling)
            if result.camera is not None and not self.config.estimate_k1:
                result = replace(result, camera=result.camera.replace(k1=0.0))
            if result.camera is not None and (confidence is None or (new_confidence or 0.0) > confidence):
                self.solver.reset(result.camera)
                entry.reinitialised = True
                entry.status = STATUS_REINITIALISED
                entry.override_camera = result.camera
                camera, confidence = result.camera, new_confidence
            elif camera is None or (confidence or 0.0) < self.config.lost_confidence:
                lost_now = True
        entry.confidence, entry.confidence_camera = confidence, camera
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
        self._maybe_fit_tripod(None if (lost_now or entry.suppress_camera) else camera, confidence)
        for estimate in released:
            self._resolve(estimate)
        self._flush()

    def on_solver_input(self, frame: FrameInput, observations: FrameObservations, detections: Detections | None) -> None:
        """Hook: called with what a frame hands the solver (subclasses record it, e.g. to write detections)."""

    def _maybe_fit_tripod(self, camera: Camera | None, confidence: float | None) -> None:
        """Online without a tripod: fit it on the confident opening frames, then hold it fixed.

        Only frames at least ``tripod_fit_min_confidence`` confident enter the fit. After
        ``tripod_provisional_frames`` of them a provisional tripod (typical delta and lambda,
        :func:`provisional_tripod`) holds the focal point in place; after
        ``tripod_fit_frames`` the fit replaces it. A fit that explains fewer than
        ``tripod_fit_min_inliers`` of its frames, or puts the tripod under 1 m or on the pitch,
        is rejected: the older half of the frames is dropped and the fit is tried again once
        enough new ones have come.
        """
        if not self.config.use_tripod or self.known_tripod is not None or self.config.mode == "batch":
            return
        if self.solver.tripod is not None and not self._provisional_tripod:
            return
        if camera is None or confidence is None or confidence < self.config.tripod_fit_min_confidence:
            return
        self._opening_cameras.append(camera)
        solver = self.graph_config.solver
        if (self.solver.tripod is None and self.config.tripod_provisional_frames
                and len(self._opening_cameras) >= self.config.tripod_provisional_frames):
            provisional = provisional_tripod(self._opening_cameras, solver.tripod_delta_prior_m or 0.2,
                                             self.graph_config.measurements.tripod_lambda_mean_m)
            if provisional is not None and plausible_position(provisional.T_w, self.pitch):
                self.solver.tripod = provisional
                self._provisional_tripod = True
                self.tripod_fit_info = {"provisional": True, "frames": len(self._opening_cameras),
                                        "reason": "typical delta and lambda; replaced once enough frames are fitted"}
                log.info("provisional tripod from %d frames: T=%s", len(self._opening_cameras),
                         np.round(provisional.T_w, 2).tolist())
        if len(self._opening_cameras) < self.config.tripod_fit_frames:
            return
        tripod, info = fit_tripod_for_run(self._opening_cameras, solver)
        if tripod is not None and (info.get("inlier_ratio", 0.0) < self.config.tripod_fit_min_inliers
                                   or not plausible_position(tripod.T_w, self.pitch)):
            info["rejected"] = (f"inlier ratio {info.get('inlier_ratio', 0.0):.2f}, T {np.round(tripod.T_w, 2).tolist()}: "
                                f"not a consistent tripod")
            log.info("online tripod fit rejected: %s", info["rejected"])
            tripod = None
        self.tripod_fit_info = info
        if tripod is not None:
            self.solver.tripod = tripod
            self._provisional_tripod = False
            log.info("tripod fitted on %d frames: T=%s delta=%.3f m", len(self._opening_cameras),
                     np.round(tripod.T_w, 2).tolist(), tripod.delta_m)
            self._opening_cameras = []
        else:
            self._opening_cameras = self._opening_cameras[len(self._opening_cameras) // 2:]

    def _resolve(self, estimate: FrameEstimate) -> None:
        for entry in self._pending:
            if entry.frame.frame_index == estimate.frame_index and entry.record is None:
                camera = None if entry.suppress_camera else (entry.override_camera or estimate.camera)
                status = entry.status if camera is not None else STATUS_FAILED
                reason = entry.reason if (camera is not None or entry.suppress_camera) else (estimate.reason or "solver failed")
                confidence = None
                if camera is not None and entry.confidence_camera is not None and \
                        np.allclose(camera.to_vector(), entry.confidence_camera.to_vector(), rtol=0, atol=1e-9):
                    confidence = entry.confidence  # online: the camera scored when the frame was added
                elif camera is not None:
                    confidence = frame_confidence(camera, entry.observations, entry.detections, self.curves, self.sampling)
                active = tuple(sorted(k for k, v in (estimate.active_factors or {}).items() if v))
                entry.record = TrackRecord(entry.frame.frame_index, entry.frame.frame_id, entry.frame.time_s, camera,
                                           _std_record(estimate) if camera is not None else {}, confidence,
                                           entry.reinitialised, status, reason, active)
                entry.detections = None
                return

    def _emit_now(self, frame: FrameInput, status: str, reason: str) -> None:
        entry = _Pending(frame, status, reason)
        entry.record = TrackRecord(frame.frame_index, frame.frame_id, frame.time_s, None, {}, None, False, status, reason)
        self._pending.append(entry)
        self._flush()

    def _break_chain(self) -> None:
        """The next frame is not linked to the previous one (no flow, re-initialise)."""
        self._lost = True
        self._prev_grey = None
        self._history.clear()

    def _flush(self) -> None:
        started = time.perf_counter()
        while self._pending and self._pending[0].record is not None:
            record = self._pending.popleft().record
            self.writer.write(record)  # records are read back from the file (RunResult.records)
        self.timings["write_s"] += time.perf_counter() - started

    def finish(self, extra_summary: dict | None = None) -> RunResult:
        """Release the smoother's last frames, write the tripod and close the run."""
        for estimate in self.solver.finish():
            self._resolve(estimate)
        for entry in self._pending:
            if entry.record is None:
                entry.record = TrackRecord(entry.frame.frame_index, entry.frame.frame_id, entry.frame.time_s, None, {},
                                           None, False, STATUS_FAILED, "no estimate released")
        self._flush()
        tripod = self.solver.tripod
        extra = dict(extra_summary or {})
        if tripod is not None:
            extra["tripod"] = {"T_w": list(map(float, tripod.T_w)), "delta_m": float(tripod.delta_m)}
            write_tripod(self.out_dir / TRIPOD_FILE, tripod, self.tripod_fit_info)
        if self.tripod_fit_info:
            extra["tripod_fit"] = self.tripod_fit_info
        extra["timings_s"] = {k: round(v, 3) for k, v in self.timings.items()}
        extra["solver_restarts"] = self.solver.rebuilds
        summary = self.writer.close(extra)
        return RunResult(self.out_dir, summary, None, tripod)


# --------------------------------------------------------------------------- whole runs


def run_frames(frames, width_px: int, height_px: int, out_dir: str | Path, config: TrackingConfig = TrackingConfig(),
               detector=None, tripod: Tripod | None = None, pitch: PitchTemplate | None = None,
               run_info: dict | None = None, progress: bool = True, total: int | None = None,
               graph_config: GraphConfig | None = None, reinit_positions=None,
               mask_paths: dict | None = None) -> RunResult:
    """Track an iterable of :class:`FrameInput` in the configured mode and write the run folder.

    In batch mode this is the paper's two-pass offline workflow: an online first pass
    (written to ``<out>/pass1``), a tripod fit, and a batch refinement with that tripod held
    fixed, or re-estimated jointly with the trajectory (``batch_tripod``), written to
    ``<out>``. Unlike the paper, the
    first pass already holds the focal point with the online tripod (provisional, then
    fitted on its confident frames: ``tripod_provisional_frames``, ``tripod_fit_frames``):
    without any tripod term, biased detections at tight zoom walked the focal point
    metres along the optical axis on the 16m preset, and the fit of such a track put T
    metres off (seed 2: 2.9 m; with the held first pass: see the README figures).
    """
    out_dir = Path(out_dir)
    if config.mode != "batch":
        run = TrackingRun(width_px, height_px, out_dir, config, detector, tripod, pitch, graph_config, run_info,
                          reinit_positions=reinit_positions, mask_paths=mask_paths)
        run_loop(run, frames, progress, total, config.mode)
        return run.finish()
    first = replace(config, mode="online")
    run = TrackingRun(width_px, height_px, out_dir / "pass1", first, detector, tripod, pitch,
                      graph_config_for(first, graph_config), run_info, keep_observations=True,
                      reinit_positions=reinit_positions, mask_paths=mask_paths)
    run_loop(run, frames, progress, total, "pass 1 (online)")
    pass1 = run.finish()
    return refine_run(pass1, run.kept, width_px, height_px, out_dir, config, tripod, pitch, run_info, progress,
                      graph_config)


def refine_run(pass1: RunResult, observations: dict[int, FrameObservations], width_px: int, height_px: int,
               out_dir: str | Path, config: TrackingConfig, tripod: Tripod | None = None,
               pitch: PitchTemplate | None = None, run_info: dict | None = None, progress: bool = True,
               graph_config: GraphConfig | None = None) -> RunResult:
    """Second pass: fit the tripod to the first pass and refine the whole track by batch LM."""
    pitch = pitch or PitchTemplate()
    graph = graph_config_for(config, graph_config)
    tracked = [r for r in pass1.records if r.camera is not None and r.frame_index in observations]
    if not tracked:
        raise RuntimeError("the first pass tracked no frame; nothing to refine")
    frames = [observations[r.frame_index] for r in tracked]
    initial = Track([FrameEstimate(r.frame_index, r.camera, reinitialised=r.reinitialised) for r in tracked])
    # Frames not consecutive in the input (a gap) are not linked.
    for previous, current in zip(tracked[:-1], tracked[1:]):
        if current.frame_index != previous.frame_index + 1:
            initial.frames[tracked.index(current)].reinitialised = True
    refiner = BatchRefiner(width_px, height_px, pitch, graph)
    started = time.perf_counter()
    joint = config.use_tripod and config.batch_tripod == "joint"
    start_tripod, fit_info = (tripod if tripod is not None else pass1.tripod), None
    if config.use_tripod and start_tripod is None and not joint:
        start_tripod, fit_info = fit_tripod_for_run([r.camera for r in tracked], graph.solver)
    track, fitted = refiner.refine(frames, initial, tripod=start_tripod if config.use_tripod else None,
                                   estimate_tripod=joint, progress=progress)
    if config.use_tripod and not joint:
        fitted = start_tripod
        if fit_info is not None:
            refiner.last_info["tripod_fit"] = fit_info
        elif pass1.summary.get("tripod_fit"):
            refiner.last_info["tripod_fit"] = {"from_first_pass": pass1.summary.get("tripod_fit")}
    elapsed = time.perf_counter() - started
    curves = TemplateCurves(pitch, line_step_m=1.0, circle_step_m=0.5)
    sampling = TemplateSampling(pitch)
    by_index = {e.frame_index: e for e in track.frames if e is not None}
    writer = TrackWriter(out_dir, width_px, height_px, also_960x540=config.write_960x540,
                         run_info={**(run_info or {}), "mode": "batch", "config": asdict(config)})
    records = []
    for record in pass1.records:
        estimate = by_index.get(record.frame_index)
        if estimate is None or estimate.camera is None:
            new = record
        else:
            obs = observations[record.frame_index]
            confidence = frame_confidence(estimate.camera, obs, None, curves, sampling) if (obs.lines_px or obs.keypoints) \
                else record.confidence
            active = tuple(sorted(k for k, v in (estimate.active_factors or {}).items() if v))
            new = TrackRecord(record.frame_index, record.frame_id, record.time_s, estimate.camera, _std_record(estimate),
                              confidence, record.reinitialised, record.status, record.reason, active)
        writer.write(new)
        records.append(new)
    pass1_s = float(pass1.summary.get("elapsed_s") or 0.0)
    extra = {"batch_refine_s": round(elapsed, 3), "pass1": str(Path(pass1.out_dir)), "pass1_s": round(pass1_s, 3),
             "fps_two_passes": round(len(pass1.records) / max(pass1_s + elapsed, 1e-9), 3)}
    if fitted is not None:
        extra["tripod"] = {"T_w": list(map(float, fitted.T_w)), "delta_m": float(fitted.delta_m)}
        write_tripod(Path(out_dir) / TRIPOD_FILE, fitted, refiner.last_info.get("tripod_fit"))
    summary = writer.close(extra)
    return RunResult(Path(out_dir), summary, records, fitted)


def run_loop(run: TrackingRun, frames, progress: bool = True, total: int | None = None, label: str = "") -> None:
    """Feed frames to a run (prefetching them in a background thread), with a progress bar."""
    flow_config = run.config.flow

    def prepare_ahead(frame: FrameInput) -> FrameInput:
        if run.config.use_flow and frame.image is not None and frame.flow_frame is None:
            frame.flow_frame = prepare(frame.image, flow_config)
        return frame

    bar = tqdm(prefetch(frames, prepare_ahead), total=total, desc=f"track {label}", unit="frame", disable=not progress)
    try:
        for frame in bar:
            run.process(frame)
            if progress:
                bar.set_postfix(run.writer.progress_postfix() if hasattr(run.writer, "progress_postfix") else {},
                                refresh=False)
    finally:
        bar.close()
