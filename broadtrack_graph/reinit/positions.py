"""Where broadcast cameras stand: focal-point guesses per camera kind, their mirror images, and
the pan that faces the centre spot.

A broadcast covers a match with several tripod cameras. Each kind lists the few positions that
cover its usual range: they name a found camera's kind (its camera id,
:mod:`broadtrack_graph.track.camera_ids`) and place the synthetic field cameras. The global search
of re-initialisation tries :data:`DEFAULT_TRIPOD_POSITIONS_W` only (and, when nothing fits there,
the main camera further back, :mod:`broadtrack_graph.reinit.mask`); a search at a guess reaches a
camera a few metres away (its wide refinement schedule). Where the numbers come from:

- ``main``: the main camera on the halfway line, on the gantry of the main stand:
  (0, 55, -12) m, the placement of the synthetic main preset; larger stadiums put it further
  back and higher on about the same line of sight to the centre spot: (0, 75, -16.5) and
  (0, 100, -22) m (the cameras that a published calibrator fitted to the SoccerNet 2022 test
  frames, main camera, have their focal point at y = 48-90 m, 5th-95th percentile, and
  z = -10 to -25 m); lower-league grounds have a low gantry a few metres behind the touchline:
  (0, 41, -6), (0, 45, -8) and (0, 38.5, -4.5) m (so close to the pitch a guess 4-5 m off does
  not converge, hence three). The three guesses on the main stand all see the centre spot
  12.3-12.4 deg below the horizon; main cameras stand at other elevations too (the main cameras
  tracked on the real clips this project is measured on were fitted at 9.3-15.6 deg, and the
  published ranges above allow up to about 27 deg): (0, 75, -12) m (9.1 deg), (0, 55, -16) m
  (16.2 deg), (0, 65, -24) m (20.3 deg) and (0, 75, -27) m (19.8 deg) are main cameras too (a camera found
  there is named ``main``), not searched: the court model places a camera wherever it stands.
- ``high-16m``: the cameras of the main stand level with the penalty areas' 16.5 m lines,
  x = +-36 m, on the main camera's gantry.
- ``high-behind``: high behind a goal, on the pitch's long axis: (-65, 0, -15) and (-75, 0, -24) m
  (the synthetic high-behind preset stands at the latter).
- ``high-corner``: high in the stand behind and to the side of a goal, on the goal line's
  extension about 35 m behind the touchline, looking into the penalty area: (+-52.5, 70, -22) m
  (a real broadcast's camera of this kind was fitted at (53.9, 71.2, -23.1) m).
- ``low-16m``: pitch-side cameras on the extension of a 16.5 m line, between the boards and the
  first rows of the stand, on a platform 5-8 m up: (+-36, 40, -5) and (+-36, 44, -8) m (so near
  the pitch a guess more than 2-3 m off does not converge, hence two per side).

Only cameras on the main camera's side (y >= 0) and behind the goals are listed: a camera at
the mirror image of a position through the centre spot (x, y -> -x, -y) sees the unlabelled
markings exactly as one at the position does (the pitch is symmetric), so the mirror adds
nothing to a search of the marking map; labelled searches try both (:func:`candidate_positions`).

Conventions: pitch frame in metres, origin at the centre spot, z down (a camera above the pitch
has z < 0); pan 0 looks towards -y, positive pan turns towards +x. No I/O.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

DEFAULT_TRIPOD_POSITIONS_W: dict[str, tuple[float, float, float]] = {
    "main": (0.0, 55.0, -12.0),
    "16m left": (-36.0, 55.0, -12.0),
    "16m right": (36.0, 55.0, -12.0),
    "high behind goal": (-65.0, 0.0, -15.0),
}
"""The positions one search of the marking map tries together (metres, pitch frame, z down)."""

MAIN_KIND = "main"
"""The kind (and camera id) of the main camera."""


@dataclass(frozen=True)
class CameraKind:
    """One kind of broadcast camera and where it stands.

    name: the kind, also the stem of the camera ids given to cameras of this kind.
    positions_w: focal-point guesses (metres, pitch frame, z down), likeliest first.
    """

    name: str
    positions_w: tuple[tuple[float, float, float], ...]


CAMERA_KINDS: tuple[CameraKind, ...] = (
    CameraKind(MAIN_KIND, ((0.0, 55.0, -12.0), (0.0, 75.0, -16.5), (0.0, 100.0, -22.0),
                           (0.0, 41.0, -6.0), (0.0, 45.0, -8.0), (0.0, 38.5, -4.5),
                           (0.0, 75.0, -12.0), (0.0, 55.0, -16.0), (0.0, 65.0, -24.0), (0.0, 75.0, -27.0))),
    CameraKind("high-16m", ((-36.0, 55.0, -12.0), (36.0, 55.0, -12.0))),
    CameraKind("high-behind", ((-65.0, 0.0, -15.0), (-75.0, 0.0, -24.0))),
    CameraKind("high-corner", ((52.5, 70.0, -22.0), (-52.5, 70.0, -22.0))),
    CameraKind("low-16m", ((36.0, 40.0, -5.0), (-36.0, 40.0, -5.0), (36.0, 44.0, -8.0), (-36.0, 44.0, -8.0))),
)
"""The camera kinds of a broadcast (module docstring), the main camera first."""

FAR_MAIN_POSITIONS_W = CAMERA_KINDS[0].positions_w[1:3]
"""Main cameras of larger stadiums: further back and higher than the default."""

NEAR_MAIN_POSITIONS_W = CAMERA_KINDS[0].positions_w[3:6]
"""Main cameras of lower-league grounds: a low gantry a few metres behind the touchline."""



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


def camera_kind(position_w) -> tuple[str, float]:
    """The kind of camera standing at position_w, and its distance (metres) to that kind's nearest guess.

    Args:
        position_w: (3,) focal point or tripod, metres, pitch frame. A position and its mirror
            image through the centre spot are the same kind.
    """
    p = np.asarray(position_w, float).reshape(3)
    best = (MAIN_KIND, math.inf)
    for kind in CAMERA_KINDS:
        for guess in kind.positions_w:
            d = min(np.linalg.norm(p - np.asarray(guess)), np.linalg.norm(p - np.asarray(mirrored_position(guess))))
            if d < best[1]:
                best = (kind.name, float(d))
    return best


def facing_pan_rad(position_w) -> float:
    """Pan (radians) that points a camera at position_w towards the centre spot (pan 0 looks to -y)."""
    x, y, _ = position_w
    return math.atan2(-x, y) if (x or y) else 0.0
