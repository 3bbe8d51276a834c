"""Why a random placement's frame was missed by a route (``bench placements --random``): the causes, first that
applies, read from a report's rows; and what a route's second look leaves it (:func:`second_look_reach`). No I/O.

The court model and the tracker look at a frame a second time, on its markings' faint look, when their camera is under
its bar (``random_placements._court_with_second_look``). A frame whose markings fix the true camera on that look
only (a motion blur or a lens blur, faint paint) is one the route can reach: the causes and the reachable frames read
both looks, the markings as found first.
"""

from __future__ import annotations

from typing import Callable

from broadtrack_graph.geometry.determinable import determinability
from broadtrack_graph.reinit.frame import frame_confidence
from broadtrack_graph.types.observations import FrameObservations

MISS_CAUSES = {"paint_not_shown": "paint not shown", "not_detected": "markings not detected",
               "truth_under_bar": "truth under the bar", "right_under_bar": "right camera under the bar",
               "route": "the route's own"}
"""Why a frame is neither found nor a twin, the first that applies (key: its words in the table): its paint does not
show enough to fix the camera (the look's faded or hidden markings), the detector's markings do not fix it on either
look the route took, the true camera itself is not confident enough to be written on them, the route's camera is the
truth or its twin but not confident enough to be written, or else the route's own miss (a wrong camera, or none)."""


def _second_look(row: dict, route: str) -> dict:
    """The route's ``second_look`` of a row ({} when it took none, or the look added no marking)."""
    return row["routes"].get(route, {}).get("second_look") or {}


def markings_detected(row: dict, route: str) -> bool:
    """Whether the detected markings fix the frame's true camera: as found, or on the route's second look."""
    return bool(row.get("markings_detected") or _second_look(row, route).get("markings_detected"))


def truth_written(row: dict, route: str) -> bool:
    """Whether the frame's true camera is confident enough to be written by ``route`` (its bar; rows written before
    the routes had their own say the row's) on the markings as found, or on the route's second look."""
    first = row["routes"].get(route, {}).get("truth_written", row["truth_written"])
    return bool(first or _second_look(row, route).get("truth_written"))


def miss_cause(row: dict, route: str) -> str:
    """The :data:`MISS_CAUSES` entry of a frame's miss by ``route`` (rows without the paint's figure count it as
    shown)."""
    if not row.get("markings_visible", True):
        return "paint_not_shown"
    if not markings_detected(row, route):
        return "not_detected"
    if not truth_written(row, route):
        return "truth_under_bar"
    return "right_under_bar" if row["routes"][route].get("right_under_bar") else "route"


def second_look_reach(truth, detections, frame_size, pitch, curves, sampling, bar_of: Callable) -> dict:
    """A route's ``second_look`` figures of a frame: whether the markings of its faint look (``detections``) fix the
    true camera, and whether the true camera is confident enough on them to be written at ``bar_of(what it
    explains)`` (a :class:`~broadtrack_graph.geometry.determinable.Determinability` -> the route's bar)."""
    markings = determinability(truth, pitch, explained_by=detections.marking_mask)
    confidence = frame_confidence(truth, FrameObservations(0, *frame_size), detections, curves, sampling)
    return {"markings_detected": markings.determinable, "truth_written": (confidence or 0.0) >= bar_of(markings),
            "truth_confidence": None if confidence is None else round(float(confidence), 3)}
