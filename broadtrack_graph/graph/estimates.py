"""Per-frame results of the solvers: camera, marginal standard deviations, active factors."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from broadtrack_graph.geometry.camera import Camera
from broadtrack_graph.geometry.state import STATE_NAMES


@dataclass
class FrameEstimate:
    """The estimate of one frame.

    frame_index: position in the clip.
    camera: the estimated camera, or None when the frame could not be estimated (see reason).
    std: (8,) marginal standard deviations in state order ``STATE_NAMES`` (px, -, rad x3, m x3),
        or None when not computed.
    active_factors: factor kind -> number of measurements used ("lines": points, "flow": matches,
        priors: 1).
    reinitialised: set by the tracking loop when the frame was re-initialised by the front end.
    reason: why camera is None (or a note), else None.
    """

    frame_index: int
    camera: Camera | None
    std: np.ndarray | None = None
    active_factors: dict[str, int] = field(default_factory=dict)
    reinitialised: bool = False
    reason: str | None = None

    def std_dict(self) -> dict[str, float] | None:
        """Standard deviations by name (pan/tilt/roll in degrees as ``*_deg``), or None."""
        if self.std is None:
            return None
        out = dict(zip(STATE_NAMES, map(float, self.std)))
        for name in ("pan", "tilt", "roll"):
            out[f"{name}_deg"] = float(np.degrees(out.pop(f"{name}_rad")))
        return out


@dataclass
class EstimateSequence:
    """A sequence of frame estimates in frame order."""

    frames: list[FrameEstimate] = field(default_factory=list)

    def __len__(self) -> int:
        return len(self.frames)

    def __iter__(self):
        return iter(self.frames)

    def __getitem__(self, i: int) -> FrameEstimate:
        return self.frames[i]

    def cameras(self) -> list[Camera | None]:
        return [f.camera for f in self.frames]

    def states(self) -> np.ndarray:
        """(N, 8) states; NaN rows for frames without a camera."""
        return np.array([f.camera.to_vector() if f.camera is not None else np.full(8, np.nan) for f in self.frames]).reshape(-1, 8)

    @classmethod
    def from_cameras(cls, cameras: list[Camera | None], first_index: int = 0) -> "EstimateSequence":
        return cls([FrameEstimate(first_index + i, c) for i, c in enumerate(cameras)])
