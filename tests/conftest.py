"""Shared fixtures: the real data beside the clone (skipped with a reason when absent)."""

from __future__ import annotations

from pathlib import Path

import pytest

SHARED_DATA = Path(__file__).resolve().parents[2] / "shared" / "data"
SN_CALIBRATION = SHARED_DATA / "sn-calibration-2022-test-main"
REAL_VIDEO = SHARED_DATA / "real-video-dev"


def _shared(folder: Path, present: Path, what: str) -> Path:
    """folder, or the test skipped with a reason when ``present`` is not there (CI has ../shared; a user's clone not)."""
    if not present.exists():
        pytest.skip(f"{what} not found at {folder} (only present beside the CI clone)")
    return folder


@pytest.fixture(scope="session")
def sn_calibration_dir() -> Path:
    """../shared/data/sn-calibration-2022-test-main: real SoccerNet calibration annotations."""
    return _shared(SN_CALIBRATION, SN_CALIBRATION / "annotations", "real SoccerNet data")


@pytest.fixture(scope="session")
def real_video_dir() -> Path:
    """../shared/data/real-video-dev: real broadcast clips."""
    return _shared(REAL_VIDEO, REAL_VIDEO / "facup-wembley-720p.mp4", "real broadcast clips")
