"""A tracking run's context: the options and collaborators that travel, as one object, through the layers.

:func:`~broadtrack_graph.actions.track.track_input` builds it once from what the user gives; it is handed to
:func:`~broadtrack_graph.track.passes.run_frames`, the offline passes and each
:class:`~broadtrack_graph.track.frame_loop.TrackingRun`. A pass that differs (batch mode's online first pass, which
keeps its observations) runs on a copy with those fields replaced (:func:`dataclasses.replace`). Adding an option
edits this class and the place that reads it. No I/O.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Callable

from broadtrack_graph.detect.detector import Detections
from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.config import GraphConfig
from broadtrack_graph.io.track_writer import RecordWritten
from broadtrack_graph.reinit.frame import frame_confidence, reinitialise
from broadtrack_graph.track.config import TrackingConfig
from broadtrack_graph.track.inputs import FrameInput
from broadtrack_graph.track.solver_settings import graph_config_for, streaming_solver_for
from broadtrack_graph.types.observations import FrameObservations

FrameDone = Callable[[FrameInput, FrameObservations | None, Detections | None], None]
"""Observer of a processed frame: (frame, what it handed the solver or None, its detections or None)."""

RecordObserver = Callable[[Path, int, int], RecordWritten]
"""Called with (run folder, width_px, height_px) whenever a pass starts writing a run folder (the online or
fixed-lag pass, batch mode's ``pass1/``, a rewrite of the folder); returns the observer of the records written
there (:data:`~broadtrack_graph.io.track_writer.RecordWritten`). The last folder it is called with holds the run's
final records."""


@dataclass(frozen=True)
class RunContext:
    """What a tracking run is given, beside its frames, their size and its run folder.

    The solver, the global search and the confidence are collaborators with defaults; tests hand fakes.
    """

    config: TrackingConfig = TrackingConfig()  # tracking options (mode, thresholds, switches)
    # A FieldDetector for image input (None when every frame brings its observations: a detections file)
    detector: object | None = None
    pitch: PitchTemplate = field(default_factory=PitchTemplate)  # the template (None given: the default pitch)
    tripod: Tripod | None = None  # a known tripod (e.g. from an earlier run): the main camera's
    tripods: dict[str, Tripod] | None = None  # known tripods by camera id (e.g. "main")
    # Solver sigmas; None: from the tracking options (graph_config_for); see graph()
    graph_config: GraphConfig | None = None
    reinit_positions: list | None = None  # candidate focal points (metres) searched instead of the default stages
    mask_paths: dict[int, Path] | None = None  # frame index -> marking-mask PNG named by a detections file
    run_info: dict | None = None  # stored in summary.json under "run"
    progress: bool = True  # show the progress bars
    on_frame_done: FrameDone | None = None  # observer of every processed frame of the (first) pass
    record_observer: RecordObserver | None = None  # sees every record of every run folder as it is written
    keep_observations: bool = False  # keep every frame's observations (the batch refinement needs them)
    # Offline modes: frames left without a camera are walked in from their neighbours' cameras
    # (track.backfill; needs a detector that finds its markings ahead)
    backfill: bool = False
    # (config, graph_config, width_px, height_px, pitch, tripod) -> StreamingSolver
    solver_factory: Callable = streaming_solver_for
    # One global search: (observations, detections, pitch, positions, curves, sampling) -> ReinitResult;
    # when and where it runs is decided by track.reinit_policy.ReinitPolicy
    reinitialise: Callable = reinitialise
    # (camera, observations, detections, curves, sampling) -> confidence in [0, 1] or None
    confidence: Callable = frame_confidence

    def __post_init__(self) -> None:
        if self.pitch is None:
            object.__setattr__(self, "pitch", PitchTemplate())

    def graph(self) -> GraphConfig:
        """The solver settings: ``graph_config`` (or the defaults) with the tracking options' switches applied."""
        return graph_config_for(self.config, self.graph_config)
