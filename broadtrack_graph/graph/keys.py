"""GTSAM symbols of the tracker's variables: one function per variable kind."""

from __future__ import annotations

import gtsam

CAMERA_CHAR = "x"
TRIPOD_CHAR = "T"


def camera_key(frame_index: int) -> int:
    """Key of the 8-vector camera state ``[f, k1, pan, tilt, roll, Cx, Cy, Cz]`` of frame t."""
    return gtsam.symbol(CAMERA_CHAR, int(frame_index))


def tripod_key() -> int:
    """Key of the shared tripod variable ``[Tx, Ty, Tz, delta]`` (metres)."""
    return gtsam.symbol(TRIPOD_CHAR, 0)


def frame_of_key(key: int) -> int:
    """Frame index of a camera key."""
    return int(gtsam.Symbol(key).index())
