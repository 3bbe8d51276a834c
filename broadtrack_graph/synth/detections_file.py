"""A synthetic detections file (no images): projected pitch markings of a generated camera track.

Cheap long inputs for track-many and its benchmark: a 20,000-frame clip is written in
about a minute, where rendering its frames would take hours. Each frame holds the visible
line and circle points with pixel noise and outliers (:mod:`broadtrack_graph.graph.simulate`),
kept, like a detector's, only inside the image (the noise pushes a few points near the border
out of it); no optical flow (a detections file carries none).
"""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

from broadtrack_graph.geometry.pitch import PitchTemplate
from broadtrack_graph.graph.simulate import SimulationSettings, simulate_frames
from broadtrack_graph.io.detections_writer import DetectionsWriter
from broadtrack_graph.synth.motion import generate_camera_track
from broadtrack_graph.types.observations import FrameObservations

SETTINGS = SimulationSettings(line_points=200, flow_matches=0, noise_px=1.0, outlier_ratio=0.05)
"""Per frame: up to 200 line points, 1 px noise, 5 % outliers, no flow."""


def write_synthetic_detections(path: str | Path, frames: int, preset: str = "main", width_px: int = 1280,
                               height_px: int = 720, seed: int = 0,
                               settings: SimulationSettings = SETTINGS) -> Path:
    """Write ``frames`` frames of detections of a generated track to ``path`` (JSON lines); returns it.

    The same arguments always give the same file. Frame ids are 1-based, 6 digits.
    """
    track = generate_camera_track(preset, frames, width_px, height_px, seed)
    path = Path(path)
    temp = path.with_name(path.name + ".partial")
    with DetectionsWriter(temp) as writer:
        for observations in simulate_frames(track.cameras, PitchTemplate(), settings, seed=seed + 1):
            writer.write(inside_image(observations), frame_id=f"{observations.frame_index + 1:06d}")
    temp.replace(path)
    return path


def inside_image(observations: FrameObservations) -> FrameObservations:
    """The frame's line points that lie in the image (pixel centres -0.5 .. size - 0.5); empty classes dropped."""
    w, h = observations.width_px, observations.height_px
    lines = {}
    for name, uv in observations.lines_px.items():
        uv = uv[(uv[:, 0] >= -0.5) & (uv[:, 0] <= w - 0.5) & (uv[:, 1] >= -0.5) & (uv[:, 1] <= h - 0.5)]
        if len(uv):
            lines[name] = uv
    return replace(observations, lines_px=lines)
