"""Whole tracking runs: online, fixed-lag, and the two-pass offline workflow (online pass, batch refinement).

Without a known tripod, the online modes track the opening frames without the tripod term, fit
(T, delta) to them (robust to outlier frames) and then hold it fixed in the tripod factor; the
offline mode does the paper's two passes: track with the online tripod (provisional, then
fitted), then a batch refinement (Levenberg-Marquardt over overlapping chunks) with that tripod
held fixed, or re-estimated with the trajectory (``batch_tripod``). The fitted tripod is written
to ``tripod.json`` for later runs of the same camera.

Both offline modes then give a camera to the frames the forward pass could not lock
(:mod:`broadtrack_graph.track.recover`: walked in from the nearest good frame, backwards for
the opening), and smooth them with their neighbours: batch mode refines them with the whole
track; fixed-lag mode refines each recovered stretch with up to ``lag_frames`` good frames on
either side (only the recovered frames' cameras are replaced). The online mode stays causal.

Each pass is a :class:`~broadtrack_graph.track.frame_loop.TrackingRun` fed by
:func:`~broadtrack_graph.track.feed.run_loop`; what a run is given travels as one
:class:`~broadtrack_graph.track.run_context.RunContext`.
"""

from __future__ import annotations

import logging
import time
from dataclasses import asdict, replace
from pathlib import Path

import cv2

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateSampling, fitting_curves
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.batch import BatchRefiner
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.estimates import EstimateSequence, FrameEstimate
from broadtrack_graph.io.run_folder import RunFolder
from broadtrack_graph.io.shots_file import SHOTS_FILE, write_shots
from broadtrack_graph.io.track_writer import TrackWriter
from broadtrack_graph.reinit.field_model import NO_MODEL
from broadtrack_graph.reinit.frame import frame_confidence, plausible_position
from broadtrack_graph.track.ahead import FramesInProcess, FramesRecipe, feed_in_process
from broadtrack_graph.track.chunked import refined_record
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.feed import run_loop
from broadtrack_graph.track.frame_loop import TrackingRun
from broadtrack_graph.track.recover import recover_gaps
from broadtrack_graph.track.result import RunResult, std_fields
from broadtrack_graph.track.run_context import RecordObserver, RunContext
from broadtrack_graph.track.shot_stream import ShotStream
from broadtrack_graph.track.tripod_check import offline_tripod
from broadtrack_graph.types.observations import FrameObservations
from broadtrack_graph.types.shot import MAIN_CAMERA_ID, NO_PITCH_KINDS, place_shot
from broadtrack_graph.types.status import FrameStatus
from broadtrack_graph.types.track_record import TrackRecord, carry_repeats

log = logging.getLogger(__name__)

_WRITER_KEYS = ("complete", "started_utc", "updated_utc", "width_px", "height_px", "frames_written",
                "frames_with_camera", "completeness", "status_counts", "mean_confidence", "last_frame_index",
                "elapsed_s", "fps", "files", "run")
"""Summary keys a TrackWriter computes itself (the rest of a summary is carried over on a rewrite)."""


def run_frames(frames, width_px: int, height_px: int, out_dir: str | Path, context: RunContext = RunContext(),
               total: int | None = None, source=None) -> RunResult:
    """Track an iterable of :class:`FrameInput` in the configured mode and write the run folder.

    In batch mode this is the paper's two-pass offline workflow: an online first pass (written to
    ``<out>/pass1``), a tripod fit, and a batch refinement with that tripod held fixed, or
    re-estimated jointly with the trajectory (``batch_tripod``), written to ``<out>``. Unlike the
    paper, the first pass already holds the focal point with the online tripod (provisional, then
    fitted on its confident frames: ``tripod_provisional_frames``, ``tripod_fit_frames``): without
    any tripod term, biased detections at tight zoom walked the focal point metres along the
    optical axis on the 16m preset, and the fit of such a track put T metres off (the figures:
    docs/BENCHMARKS.md, "Why the defaults").

    The context (:class:`~broadtrack_graph.track.run_context.RunContext`) says the rest: its ``on_frame_done``
    observes every processed frame of the (first) pass, e.g. to collect the detector's player boxes; its
    ``record_observer`` sees every record of every run folder as it is written (e.g. to put the players on the
    pitch as the run goes). ``total``: the frames expected (for the progress bar), or None.

    With a detector (image input), the shot step runs on the frames as they are decoded
    (:class:`~broadtrack_graph.track.shot_stream.ShotStream`): ``shots.json`` is written to the run
    folder, and a clip with no shot of the main camera says so in one line (summary ``note``). ``source``: the open
    frame source the frames come from, when a process of its own may open it again and prepare them
    (:func:`~broadtrack_graph.track.ahead.feed_in_process`); None: they are prepared in a thread.
    """
    config = context.config
    out_dir = Path(out_dir)
    RunFolder(out_dir).clear()  # nothing of an earlier run into this folder survives (tripod.json, pass1/, ...)
    recover = config.mode != "online" and config.recover_max_frames > 0
    given: dict[int, FrameObservations] = {}  # the observations a detections file brought (for the recovery)
    frames = _capturing(frames, given) if recover else frames
    stream = None
    recipe = FramesRecipe.of(source) if source is not None else None
    if feed_in_process(recipe, context.detector, total, (width_px, height_px)):
        # The shot step and the camera-free steps in a process of their own, which opens the input again.
        # The loop reads a frame's pixels only for a field model or an observer of the frames: else the frames whose
        # markings and flow frame were made there stay there (a 1080p image is 6 MB to copy out of shared memory).
        send_pixels = context.on_frame_done is not None or str(config.reinit_model) != NO_MODEL
        stream = frames = FramesInProcess(recipe, context.detector, config, cv2.getNumThreads(), (width_px, height_px),
                                          send_pixels)
    elif context.detector is not None and (config.detect_shots or config.mask_graphics):
        # Image input: shots (cuts, other views) and the static graphics mask, computed as frames are decoded.
        stream = ShotStream.for_run(frames, config.detect_shots, config.mask_graphics, context.detector)
        frames = stream
    if config.mode != "batch":  # fixed-lag keeps no observations of its own (a long run would grow without bound)
        run = TrackingRun(width_px, height_px, out_dir, replace(context, backfill=recover))
        _observe(run.writer, context.record_observer)
        run_loop(run, frames, total, config.mode)
        result = run.finish(_shots_summary(stream, out_dir, run.shot_camera_ids))
        if run.backfill is not None and run.backfill.recovered:
            result = _rewritten(result, _backfilled(result.records, run.backfill.recovered), width_px, height_px,
                                context, {"backfilled_frames": len(run.backfill.recovered)})
        if not recover or not given:
            return result
        return recover_fixed_lag(result, given, width_px, height_px, context)
    first = replace(config, mode="online")
    run = TrackingRun(width_px, height_px, RunFolder(out_dir).pass1().path,
                      replace(context, config=first, keep_observations=True, backfill=recover))
    _observe(run.writer, context.record_observer)
    run_loop(run, frames, total, "pass 1 (online)")
    pass1 = run.finish(_shots_summary(stream, out_dir, run.shot_camera_ids))
    if not any(r.camera is not None for r in pass1.records) and stream is not None and stream.shots:
        return pass1
    observations = run.kept
    if run.backfill is not None and run.backfill.recovered:
        # The back-filled frames enter the refinement with the points they were named with.
        observations.update({i: b.observations for i, b in run.backfill.recovered.items()})
        pass1 = RunResult(pass1.out_dir, {**pass1.summary, "backfilled_frames": len(run.backfill.recovered)},
                          _backfilled(pass1.records, run.backfill.recovered), pass1.tripod, pass1.tripods)
    if recover:
        observations = {**given, **run.kept}
        recovery = recover_gaps(pass1.records, observations, context.pitch, context.graph(),
                                config.confidence_threshold, config.recover_max_frames, pass1.tripod or context.tripod,
                                {**(pass1.tripods or {}), **(context.tripods or {})})
        pass1 = RunResult(pass1.out_dir, {**pass1.summary, "offline_recovery": recovery.info()}, recovery.records,
                          pass1.tripod, pass1.tripods)
    return refine_run(pass1, observations, width_px, height_px, out_dir, context)


def _observe(writer: TrackWriter, record_observer: RecordObserver | None) -> TrackWriter:
    """Hand the writer's records to the observer of its folder (nothing without one); returns the writer."""
    if record_observer is not None:
        writer.on_write = record_observer(writer.out_dir, writer.width_px, writer.height_px)
    return writer


def _shots_summary(stream: ShotStream | FramesInProcess | None, out_dir: Path, camera_ids: dict[int, str]) -> dict:
    """Write shots.json (when shots were detected) with each shot's camera, and the summary fields about them.

    camera_ids: shot index -> the camera id the tracker found for it. A pitch shot's kind becomes
    ``main`` (the main camera), ``other-camera`` (another pitch camera) or ``pitch`` (no camera placed).
    """
    if stream is None or not stream.detects_shots:
        return {}
    shots = [place_shot(shot, camera_ids.get(k)) for k, shot in enumerate(stream.shots)]
    write_shots(out_dir / SHOTS_FILE, shots)
    extra = {"shots": len(shots), "other_view_shots": sum(s.kind in NO_PITCH_KINDS for s in shots),
             "cameras": sorted({s.camera_id for s in shots if s.camera_id is not None})}
    if shots and all(s.kind in NO_PITCH_KINDS for s in shots):
        kinds = sorted({s.kind for s in shots})
        extra["note"] = (f"no shot of a pitch camera in the input ({len(shots)} shot(s) of {', '.join(kinds)}): "
                         "no camera written")
        log.warning("%s", extra["note"])
    return extra


def _capturing(frames, store: dict[int, FrameObservations]):
    """The frames, noting the observations each one brings (a detections file's) in store."""
    for frame in frames:
        if frame.observations is not None:
            store[frame.frame_index] = replace(frame.observations, marking_mask=None, flow=None)
        yield frame


def recover_fixed_lag(result: RunResult, observations: dict[int, FrameObservations], width_px: int, height_px: int,
                      context: RunContext) -> RunResult:
    """Fixed-lag mode: recover the frames without a camera, smooth each recovered stretch with up to
    ``lag_frames`` good frames on either side (batch LM, tripod held), and rewrite the run folder
    (the context's ``record_observer`` sees the records: see :func:`run_frames`)."""
    config, pitch, graph = context.config, context.pitch, context.graph()
    recovery = recover_gaps(result.records, observations, pitch, graph, config.confidence_threshold,
                            config.recover_max_frames, result.tripod, result.tripods)
    if not recovery.recovered:
        return result
    records = recovery.records
    recovered = set(recovery.recovered)
    position = {r.frame_index: i for i, r in enumerate(records)}
    refiner = BatchRefiner(width_px, height_px, pitch, graph)
    curves, sampling = fitting_curves(pitch), TemplateSampling(pitch)
    for first, last in recovery.gaps:
        lo = max(0, position[first] - config.lag_frames)
        hi = min(len(records), position[last] + 1 + config.lag_frames)
        window = [r for r in records[lo:hi] if r.camera is not None and r.frame_index in observations]
        # The camera the gap's recovered frames were walked from (its first frame may be one the walks did not reach).
        gap_camera = next((r.camera_id for r in window if first <= r.frame_index <= last and r.frame_index in recovered),
                          None)
        window = [r for r in window if r.camera_id == gap_camera]  # one camera's frames, with its tripod
        if not any(r.frame_index in recovered for r in window):
            continue
        initial = EstimateSequence([FrameEstimate(r.frame_index, r.camera) for r in window])
        for k in range(1, len(window)):
            if window[k].frame_index != window[k - 1].frame_index + 1:
                initial.frames[k].reinitialised = True
        track, _ = refiner.refine([observations[r.frame_index] for r in window], initial,
                                  tripod=result.tripod_of(gap_camera), estimate_tripod=False)
        for estimate in track.frames:
            if estimate is None or estimate.camera is None or estimate.frame_index not in recovered or \
                    not plausible_position(estimate.camera.position_m, pitch):
                continue
            i = position[estimate.frame_index]
            obs = observations[estimate.frame_index]
            records[i] = replace(records[i], camera=estimate.camera, std=std_fields(estimate),
                                 confidence=frame_confidence(estimate.camera, obs, None, curves, sampling))
    return _rewritten(result, records, width_px, height_px, context, {"offline_recovery": recovery.info()})


def _backfilled(records: list[TrackRecord], recovered: dict) -> list[TrackRecord]:
    """The records with the back-fill's cameras (:class:`~broadtrack_graph.track.backfill.Backfilled`) put in."""
    out = []
    for record in records:
        found = recovered.get(record.frame_index)
        if found is not None and record.camera is None:
            record = replace(record, camera=found.camera, confidence=found.confidence, status=FrameStatus.TRACKED,
                             reinitialised=False, std={}, camera_id=found.camera_id,
                             reason=f"back-filled offline from frame {found.source}",
                             active_factors=("lines",))
        out.append(record)
    return out


def _rewritten(result: RunResult, records: list[TrackRecord], width_px: int, height_px: int, context: RunContext,
               extra: dict) -> RunResult:
    """The run folder written again with these records (offline recovery, back-fill); the summary keeps its fields."""
    kept = {k: v for k, v in result.summary.items() if k not in _WRITER_KEYS}
    writer = _observe(TrackWriter(result.out_dir, width_px, height_px, also_960x540=context.config.write_960x540,
                                  run_info=result.summary.get("run", context.run_info or {})), context.record_observer)
    records = carry_repeats(records)
    for record in records:
        writer.write(record)
    summary = writer.close({**kept, **extra})
    return RunResult(Path(result.out_dir), summary, records, result.tripod, result.tripods)


def refine_run(pass1: RunResult, observations: dict[int, FrameObservations], width_px: int, height_px: int,
               out_dir: str | Path, context: RunContext) -> RunResult:
    """Second pass: fit the tripod to the first pass and refine the whole track by batch LM, one camera
    (camera id) at a time with its own tripod (the context's ``tripod`` and ``tripods`` are the known ones; its
    ``record_observer``: see :func:`run_frames`)."""
    config, pitch, graph = context.config, context.pitch, context.graph()
    tripod, tripods = context.tripod, context.tripods
    tracked = [r for r in pass1.records if r.camera is not None and r.frame_index in observations]
    if not tracked:
        raise RuntimeError("the first pass tracked no frame; nothing to refine")
    groups: dict[str | None, list[TrackRecord]] = {}
    for record in tracked:
        groups.setdefault(record.camera_id, []).append(record)
    single = len(groups) == 1
    refiner = BatchRefiner(width_px, height_px, pitch, graph)
    started = time.perf_counter()
    joint = config.use_tripod and config.batch_tripod == "joint"
    by_index: dict[int, FrameEstimate] = {}
    fitted_by_camera: dict[str, Tripod] = {}
    fit_infos: dict = {}
    fitted = None
    for camera_id, group in groups.items():
        given = (tripods or {}).get(camera_id) if camera_id is not None else None
        if given is None and (single or camera_id in (None, MAIN_CAMERA_ID)):
            given = tripod
        start_tripod = given if given is not None else (pass1.tripod if single else pass1.tripod_of(camera_id))
        track, camera_tripod, info = _refine_camera(refiner, group, observations, config, graph, pitch, start_tripod,
                                                    joint, context.progress, pass1.summary if single else {})
        by_index.update({e.frame_index: e for e in track.frames if e is not None})
        if info is not None:
            fit_infos[str(camera_id)] = info
        if camera_tripod is not None and camera_id is not None:
            fitted_by_camera[camera_id] = camera_tripod
        if camera_tripod is not None and (fitted is None or single or camera_id == MAIN_CAMERA_ID):
            fitted = camera_tripod
    if single and fit_infos:
        refiner.last_info["tripod_fit"] = next(iter(fit_infos.values()))
    elif fit_infos:
        refiner.last_info["tripod_fit"] = fit_infos
    elapsed = time.perf_counter() - started
    curves = fitting_curves(pitch)
    sampling = TemplateSampling(pitch)
    writer = _observe(TrackWriter(out_dir, width_px, height_px, also_960x540=config.write_960x540,
                                  run_info={**(context.run_info or {}), "mode": "batch", "config": asdict(config)}),
                      context.record_observer)
    records = carry_repeats([refined_record(record, by_index.get(record.frame_index),
                                            observations.get(record.frame_index), curves, sampling)
                             for record in pass1.records])
    for record in records:
        writer.write(record)
    pass1_s = float(pass1.summary.get("elapsed_s") or 0.0)
    extra = {"batch_refine_s": round(elapsed, 3), "pass1": str(Path(pass1.out_dir)), "pass1_s": round(pass1_s, 3),
             "fps_two_passes": round(len(pass1.records) / max(pass1_s + elapsed, 1e-9), 3)}
    if "offline_recovery" in pass1.summary:
        extra["offline_recovery"] = pass1.summary["offline_recovery"]
    if fitted is not None:
        extra["tripod"] = {"T_w": list(map(float, fitted.T_w)), "delta_m": float(fitted.delta_m)}
        RunFolder(out_dir).write_tripod(fitted, refiner.last_info.get("tripod_fit"), fitted_by_camera)
    if refiner.last_info.get("tripod_fit"):
        extra["tripod_fit"] = refiner.last_info["tripod_fit"]  # as the online run's summary: why this tripod
    summary = writer.close(extra)
    return RunResult(Path(out_dir), summary, records, fitted, fitted_by_camera)


def _refine_camera(refiner: BatchRefiner, tracked: list[TrackRecord], observations: dict[int, FrameObservations],
                   config: TrackingConfig, graph: GraphConfig, pitch: PitchTemplate, start_tripod: Tripod | None,
                   joint: bool, progress: bool,
                   first_pass_summary: dict) -> tuple[EstimateSequence, Tripod | None, dict | None]:
    """Batch LM over one camera's frames: (refined track, its tripod, the tripod fit's report or None). Without a
    tripod given, the one :func:`~broadtrack_graph.track.tripod_check.offline_tripod` chooses."""
    frames = [observations[r.frame_index] for r in tracked]
    initial = EstimateSequence([FrameEstimate(r.frame_index, r.camera, reinitialised=r.reinitialised) for r in tracked])
    # Frames not consecutive in the input (a gap, another camera's shot between) are not linked.
    for k in range(1, len(tracked)):
        if tracked[k].frame_index != tracked[k - 1].frame_index + 1:
            initial.frames[k].reinitialised = True
    fit_info = None
    if config.use_tripod and start_tripod is None:
        start_tripod, fit_info = offline_tripod([r.camera for r in tracked], config, graph, pitch)
    track, fitted = refiner.refine(frames, initial, tripod=start_tripod if config.use_tripod else None,
                                   estimate_tripod=joint, progress=progress)
    if config.use_tripod and not joint:
        fitted = start_tripod
        if fit_info is None and first_pass_summary.get("tripod_fit"):
            fit_info = {"from_first_pass": first_pass_summary.get("tripod_fit")}
    elif joint and refiner.last_info.get("tripod_fit"):
        fit_info = refiner.last_info.get("tripod_fit")
    return track, fitted, fit_info
