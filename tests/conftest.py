"""Shared fixtures: the real SoccerNet data beside the clone (skipped with a reason when absent)."""

from __future__ import annotations

from pathlib import Path

import pytest

SHARED_DATA = Path(__file__).resolve().parents[2] / "shared" / "data"
SN_CALIBRATION = SHARED_DATA / "sn-calibration-2022-test-main"


@pytest.fixture(scope="session")
def sn_calibration_dir() -> Path:
    """../shared/data/sn-calibration-2022-test-main (CI has it beside the clone; a user's clone does not)."""
    if not (SN_CALIBRATION / "annotations").is_dir():
        pytest.skip(f"real SoccerNet data not found at {SN_CALIBRATION} (only present beside the CI clone)")
    return SN_CALIBRATION


REAL_VIDEO = SHARED_DATA / "real-video-dev"


@pytest.fixture(scope="session")
def real_video_dir() -> Path:
    """../shared/data/real-video-dev: real broadcast clips (CI has them beside the clone; a user's clone does not)."""
    if not (REAL_VIDEO / "facup-wembley-720p.mp4").is_file():
        pytest.skip(f"real broadcast clips not found at {REAL_VIDEO} (only present beside the CI clone)")
    return REAL_VIDEO
