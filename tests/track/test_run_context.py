"""The run context (broadtrack_graph.track.run_context): defaults, the pitch filled in, the solver settings."""

from __future__ import annotations

from dataclasses import FrozenInstanceError, replace

import pytest

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.reinit.frame import frame_confidence, reinitialise
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.run_context import RunContext
from broadtrack_graph.track.solver_settings import graph_config_for, streaming_solver_for


def test_the_defaults_are_the_product_s_collaborators():
    context = RunContext()
    assert context.config == TrackingConfig() and context.detector is None and context.progress
    assert context.solver_factory is streaming_solver_for and context.reinitialise is reinitialise
    assert context.confidence is frame_confidence and not context.keep_observations and not context.backfill
    assert isinstance(context.pitch, PitchTemplate)


def test_no_pitch_given_is_the_default_pitch_and_a_given_one_is_kept():
    assert isinstance(RunContext(pitch=None).pitch, PitchTemplate)
    pitch = PitchTemplate()
    assert RunContext(pitch=pitch).pitch is pitch


def test_the_solver_settings_follow_the_tracking_switches():
    config = TrackingConfig(use_flow=False, estimate_k1=False)
    assert RunContext(config).graph() == graph_config_for(config)
    base = GraphConfig()
    assert RunContext(config, graph_config=base).graph() == graph_config_for(config, base)
    assert graph_config_for(config).measurements.line_loss == "cauchy"
    redescending = TrackingConfig(line_loss="geman-mcclure")
    assert graph_config_for(redescending).measurements.line_loss == "geman-mcclure"
    with pytest.raises(ValueError, match="line_loss must be one of"):
        TrackingConfig(line_loss="huber")


def test_a_pass_that_differs_runs_on_a_copy():
    context = RunContext(TrackingConfig(mode="batch"))
    first = replace(context, config=replace(context.config, mode="online"), keep_observations=True)
    assert first.config.mode == "online" and first.keep_observations and context.config.mode == "batch"
    assert first.pitch is context.pitch
    with pytest.raises(FrozenInstanceError):
        context.progress = False
