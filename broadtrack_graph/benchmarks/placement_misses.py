"""Why a random placement's frame was missed by a route (``bench placements --random``): the causes, first that
applies, read from a report's rows. No I/O."""

from __future__ import annotations

MISS_CAUSES = {"paint_not_shown": "paint not shown", "not_detected": "markings not detected",
               "truth_under_bar": "truth under the bar", "right_under_bar": "right camera under the bar",
               "route": "the route's own"}
"""Why a frame is neither found nor a twin, the first that applies (key: its words in the table): its paint does not
show enough to fix the camera (the look's faded or hidden markings), the detector's markings do not fix it, the true
camera itself is not confident enough to be written on them, the route's camera is the truth or its twin but not
confident enough to be written, or else the route's own miss (a wrong camera, or none)."""


def truth_written(row: dict, route: str) -> bool:
    """Whether the frame's true camera is confident enough to be written by ``route`` (its bar; rows written before
    the routes had their own say the row's)."""
    return bool(row["routes"].get(route, {}).get("truth_written", row["truth_written"]))


def miss_cause(row: dict, route: str) -> str:
    """The :data:`MISS_CAUSES` entry of a frame's miss by ``route`` (rows without the paint's figure count it as
    shown)."""
    if not row.get("markings_visible", True):
        return "paint_not_shown"
    if not row.get("markings_detected"):
        return "not_detected"
    if not truth_written(row, route):
        return "truth_under_bar"
    return "right_under_bar" if row["routes"][route].get("right_under_bar") else "route"
