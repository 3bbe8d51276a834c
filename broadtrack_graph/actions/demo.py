"""The demo: render the embedded default clip, track it online and smoothed, evaluate, draw, compare.

Everything it needs is made here (no download): a synthetic main-camera clip with
exact ground truth (:mod:`broadtrack_graph.synth`), the weight-free detector, the
online iSAM2 tracker and the fixed-lag smoother, the SoccerNet metric against the
clip's ground-truth line annotations, an overlay video and the filter-vs-smoother
comparison (table + plots).
"""

from __future__ import annotations

import json
import logging
from dataclasses import dataclass
from pathlib import Path

from broadtrack_graph.actions.compare import compare_runs
from broadtrack_graph.actions.track import DetectorOptions, track_input
from broadtrack_graph.products.compare_report import format_table
from broadtrack_graph.products.overlay import write_overlay
from broadtrack_graph.synth.writer import write_synthetic_clip
from broadtrack_graph.track.config import TrackingConfig

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class DemoSettings:
    """What the demo renders and runs."""

    frames: int = 250  # clip length (10 s at 25 fps)
    width_px: int = 1920
    height_px: int = 1080
    preset: str = "main"
    seed: int = 0
    lag_frames: int = 25  # fixed-lag smoother lag
    overlay: bool = True  # write the overlay video


def run_demo(out_dir: str | Path, settings: DemoSettings = DemoSettings(), progress: bool = True) -> dict:
    """Run the whole demo into ``out_dir`` and return where everything is, with the headline figures."""
    out = Path(out_dir)
    clip = out / "clip"
    summary = write_synthetic_clip(clip, preset=settings.preset, frame_count=settings.frames,
                                   width_px=settings.width_px, height_px=settings.height_px, seed=settings.seed,
                                   progress=progress)
    runs = {}
    for name, config in (("online", TrackingConfig(mode="online")),
                         ("fixed-lag", TrackingConfig(mode="fixed-lag", lag_frames=settings.lag_frames))):
        runs[name] = track_input(clip, out / name, config, DetectorOptions("weightfree"), progress=progress).out_dir
    truth_tripod = json.loads((clip / "tripod.json").read_text())
    report = compare_runs(list(runs.values()), names=list(runs), annotations_path=clip / "Labels-GameState.json",
                          ground_truth_dir=clip / "cameras", out_dir=out / "compare", tripod_T_w=truth_tripod["T_w"])
    overlay = None
    if settings.overlay:
        overlay = write_overlay(runs["fixed-lag"], clip, out / "overlay_fixed_lag.mp4", progress=progress)["out"]
    return {
        "clip": str(clip), "render_s_per_frame": summary.seconds_per_frame,
        "runs": {name: str(path) for name, path in runs.items()},
        "compare": str(out / "compare"), "overlay": None if overlay is None else str(overlay),
        "table": format_table(report), "report": report,
    }
