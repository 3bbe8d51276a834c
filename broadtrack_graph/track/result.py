"""What a tracking run produced (RunResult), and the record fields of a solver estimate."""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from broadtrack_graph.geometry.tripod import Tripod
from broadtrack_graph.graph.estimates import FrameEstimate
from broadtrack_graph.io.run_folder import read_track
from broadtrack_graph.types.track_record import TrackRecord


@dataclass
class RunResult:
    """What a run produced: its folder, summary, the per-frame records, the tripod used (the main camera's,
    else the last camera's) and every camera's tripod by camera id.

    ``records`` are read back from the run's ``track.jsonl`` on first use when the run did not
    keep them in memory (a long run does not: a record is about 1.5 KB, 200 MB over a match).
    """

    out_dir: Path
    summary: dict
    kept_records: list[TrackRecord] | None = None
    tripod: Tripod | None = None
    tripods: dict[str, Tripod] | None = None

    def tripod_of(self, camera_id: str | None) -> Tripod | None:
        """The tripod of one camera: its own, else (a run without camera ids) the run's."""
        if self.tripods:
            return self.tripods.get(camera_id) if camera_id is not None else None
        return self.tripod

    @property
    def records(self) -> list[TrackRecord]:
        if self.kept_records is None:
            self.kept_records = read_track(self.out_dir).records
        return self.kept_records


def std_fields(estimate: FrameEstimate) -> dict:
    """The standard deviations of an estimate as track-record fields (empty without them).

    Returns:
        {"focal_std_px": px, "k1_std": -, "pan_std_deg" / "tilt_std_deg" / "roll_std_deg": degrees,
        "position_std_m": (3,) metres}.
    """
    if estimate.std is None:
        return {}
    s = np.asarray(estimate.std, float)
    return {"focal_std_px": float(s[0]), "k1_std": float(s[1]), "pan_std_deg": math.degrees(s[2]),
            "tilt_std_deg": math.degrees(s[3]), "roll_std_deg": math.degrees(s[4]), "position_std_m": s[5:8].copy()}
