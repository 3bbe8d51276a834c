"""The solver settings a run's tracking options imply: the factor graph's configuration and the streaming solver of
the mode. No I/O."""

from __future__ import annotations

from dataclasses import replace

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.graph.streaming import FixedLagStreamingSolver, OnlineStreamingSolver, StreamingSolver
from broadtrack_graph.track.config import TrackingConfig


def graph_config_for(config: TrackingConfig, base: GraphConfig | None = None) -> GraphConfig:
    """The solver settings implied by the tracking options (flow / tripod / k1 switches, the line factor's loss)."""
    base = base or GraphConfig()
    changes = {"use_flow": config.use_flow, "use_tripod": config.use_tripod}
    graph = replace(base, **{k: v for k, v in changes.items() if hasattr(base, k)})
    if config.line_loss != graph.measurements.line_loss:
        graph = replace(graph, measurements=replace(graph.measurements, line_loss=config.line_loss))
    if not config.estimate_k1 and hasattr(graph.priors, "k1_fixed"):
        graph = replace(graph, priors=replace(graph.priors, k1_fixed=True))
    return graph


def streaming_solver_for(config: TrackingConfig, graph: GraphConfig, width_px: int, height_px: int,
                         pitch: PitchTemplate, tripod: Tripod | None) -> StreamingSolver:
    """The streaming solver of a mode: fixed-lag for "fixed-lag", else online (batch's first pass is online)."""
    if config.mode == "fixed-lag":
        return FixedLagStreamingSolver(width_px, height_px, pitch, graph, tripod, lag=config.lag_frames)
    return OnlineStreamingSolver(width_px, height_px, pitch, graph, tripod)
