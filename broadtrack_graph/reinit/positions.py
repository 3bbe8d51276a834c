"""Default focal points of the common broadcast cameras (tried when no tripod is known), their
mirror images through the centre spot, and the pan that faces the centre spot.

Conventions: pitch frame in metres, origin at the centre spot, z down (a camera above the pitch
has z < 0); pan 0 looks towards -y, positive pan turns towards +x. No I/O.
"""

from __future__ import annotations

import math

DEFAULT_TRIPOD_POSITIONS_W: dict[str, tuple[float, float, float]] = {
    "main": (0.0, 55.0, -12.0),
    "16m left": (-36.0, 55.0, -12.0),
    "16m right": (36.0, 55.0, -12.0),
    "high behind goal": (-65.0, 0.0, -15.0),
}
"""Focal-point guesses for the common broadcast cameras (metres, pitch frame, z down)."""


def mirrored_position(position_w) -> tuple[float, float, float]:
    """The position reflected through the pitch centre (x, y -> -x, -y)."""
    x, y, z = position_w
    return (-x, -y, z)


def candidate_positions(include_mirrored: bool = True) -> list[tuple[float, float, float]]:
    """The default tripod positions, plus their reflections through the centre (labels may be mirrored)."""
    positions = list(DEFAULT_TRIPOD_POSITIONS_W.values())
    if include_mirrored:
        positions += [mirrored_position(p) for p in DEFAULT_TRIPOD_POSITIONS_W.values()]
    return positions


def facing_pan_rad(position_w) -> float:
    """Pan (radians) that points a camera at position_w towards the centre spot (pan 0 looks to -y)."""
    x, y, _ = position_w
    return math.atan2(-x, y) if (x or y) else 0.0
