"""Offline refinement of a long clip in independent windows: the stages track-many runs in parallel.

The one-process offline run (:func:`~broadtrack_graph.track.passes.refine_run`) refines
overlapping chunks one after the other, each started from the previous one. Here every
window (:class:`~broadtrack_graph.track.chunks.Chunk`) is refined on its own, from the first
pass's cameras and one tripod fitted to the whole first pass (a reduce over all windows), so
that windows can run at the same time on different workers; :func:`~broadtrack_graph.track.chunks.stitch`
then keeps each window's own frames. The same windows run in one process give the same
numbers (the bench ``scale`` compares both, and against the chained one-process run).
"""

from __future__ import annotations

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.template import TemplateCurves, TemplateSampling, fitting_curves
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.batch import BatchRefiner
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.estimates import EstimateSequence, FrameEstimate
from broadtrack_graph.reinit.frame import frame_confidence, plausible_position
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.result import std_fields
from broadtrack_graph.track.solver_settings import graph_config_for
from broadtrack_graph.track.tripod_check import offline_tripod
from broadtrack_graph.types.observations import FrameObservations
from broadtrack_graph.types.track_record import TrackRecord, carry_repeats


def fit_clip_tripod(records: list[TrackRecord], config: TrackingConfig, graph_config: GraphConfig | None = None,
                    pitch: PitchTemplate | None = None) -> tuple[Tripod | None, dict]:
    """The reduce between the stages: one tripod for every first-pass camera of a clip, as the one-process offline
    pass chooses it (:func:`~broadtrack_graph.track.tripod_check.offline_tripod`)."""
    graph = graph_config_for(config, graph_config)
    return offline_tripod([r.camera for r in records if r.camera is not None], config, graph, pitch or PitchTemplate())


def refine_window_records(records: list[TrackRecord], observations: dict[int, FrameObservations], width_px: int,
                          height_px: int, config: TrackingConfig, tripod: Tripod | None,
                          pitch: PitchTemplate | None = None,
                          graph_config: GraphConfig | None = None) -> list[TrackRecord]:
    """Refine one window of first-pass records by batch LM with the tripod held fixed.

    Args:
        records: the first pass's records of the window, in frame order.
        observations: frame index -> observations (pixels at width_px x height_px) of the window.
        tripod: the clip's tripod (None: no tripod factor).

    Returns:
        One record per input record: refined where the first pass had a camera, as is elsewhere.
    """
    pitch = pitch or PitchTemplate()
    tracked = [r for r in records if r.camera is not None and r.frame_index in observations]
    if not tracked:
        return list(records)
    initial = EstimateSequence([FrameEstimate(r.frame_index, r.camera, reinitialised=r.reinitialised) for r in tracked])
    for n in range(1, len(tracked)):  # frames not consecutive in the input (a gap) are not linked
        if tracked[n].frame_index != tracked[n - 1].frame_index + 1:
            initial.frames[n].reinitialised = True
    refiner = BatchRefiner(width_px, height_px, pitch, graph_config_for(config, graph_config))
    estimates = refiner.refine_window([observations[r.frame_index] for r in tracked], initial, tripod)
    by_index = {e.frame_index: e for e in estimates if e is not None}
    curves = fitting_curves(pitch)
    sampling = TemplateSampling(pitch)
    return carry_repeats([refined_record(r, by_index.get(r.frame_index), observations.get(r.frame_index), curves,
                                         sampling) for r in records])


def refined_record(record: TrackRecord, estimate: FrameEstimate | None, observations: FrameObservations | None,
                   curves: TemplateCurves, sampling: TemplateSampling) -> TrackRecord:
    """A first-pass record with the refined camera, its std, confidence and active factors (as is without one, or
    when the refined camera's focal point is not a broadcast camera's,
    :func:`~broadtrack_graph.reinit.frame.plausible_position`: the first pass judged its own camera)."""
    if estimate is None or estimate.camera is None or observations is None or \
            not plausible_position(estimate.camera.position_m, curves.pitch):
        return record
    confidence = (frame_confidence(estimate.camera, observations, None, curves, sampling)
                  if (observations.lines_px or observations.keypoints) else record.confidence)
    active = tuple(sorted(k for k, v in (estimate.active_factors or {}).items() if v))
    return TrackRecord(record.frame_index, record.frame_id, record.time_s, estimate.camera, std_fields(estimate),
                       confidence, record.reinitialised, record.status, record.reason, active, record.camera_id)
