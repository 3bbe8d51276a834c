"""Argument checks at the door: argparse ``type=`` callables, one per kind of value.

Each callable turns the command-line string into a value or raises
``argparse.ArgumentTypeError`` with one line naming the value and the remedy; the
parser (:func:`broadtrack_graph.cli.build_parser`) prints it as one line and exits 2. Used by
the commands and by the ``bench`` suites' options (hence at the package's root).
"""

from __future__ import annotations

import argparse
import math


def _number(text: str, kind=float) -> float:
    try:
        value = kind(text)
    except (TypeError, ValueError):
        raise argparse.ArgumentTypeError(f"'{text}' is not {'an integer' if kind is int else 'a number'}") from None
    if kind is float and not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"'{text}' is not a finite number; give a finite value")
    return value


def int_at_least(minimum: int, what: str = ""):
    """An integer >= minimum (e.g. ``int_at_least(1)`` for --lag, --frames, --jobs)."""

    def parse(text: str) -> int:
        value = _number(text, int)
        if value < minimum:
            raise argparse.ArgumentTypeError(f"{value} is too small; give an integer >= {minimum}{what}")
        return value

    parse.__name__ = f"integer >= {minimum}"
    return parse


def int_between(low: int, high: int):
    """An integer in [low, high] (e.g. a JPEG quality)."""
    return _in_range(int, low, high, f"[{low}, {high}]", "an integer")


def float_between(low: float, high: float):
    """A finite number strictly between low and high (e.g. a camera's distance or elevation)."""
    return _in_range(float, low, high, f"({low:g}, {high:g})", "a number")


def _in_range(kind, low, high, interval: str, what: str):
    """A ``kind`` value in ``interval`` (``[low, high]`` or the open ``(low, high)``)."""
    closed = interval.startswith("[")

    def parse(text: str):
        value = _number(text, kind)
        if not (low <= value <= high if closed else low < value < high):
            raise argparse.ArgumentTypeError(f"{value:g} is out of range; give {what} in {interval}")
        return value

    parse.__name__ = f"{what} in {interval}"
    return parse


def finite_float(text: str) -> float:
    """Any finite number (no nan, no inf)."""
    return _number(text)


def positive_float(text: str) -> float:
    """A finite number > 0 (e.g. a pixel threshold tau)."""
    value = _number(text)
    if value <= 0:
        raise argparse.ArgumentTypeError(f"{value:g} is not positive; give a number > 0")
    return value


def unit_interval(text: str) -> float:
    """A number in [0, 1] (e.g. a confidence threshold)."""
    value = _number(text)
    if not 0.0 <= value <= 1.0:
        raise argparse.ArgumentTypeError(f"{value:g} is outside [0, 1]; give a number between 0 and 1")
    return value


def positive_share(text: str) -> float:
    """A number in (0, 1] (e.g. the share of the light a shadow keeps)."""
    value = _number(text)
    if not 0.0 < value <= 1.0:
        raise argparse.ArgumentTypeError(f"{value:g} is outside (0, 1]; give a number above 0, at most 1")
    return value


def image_side(text: str) -> int:
    """An image width or height in pixels, 16 .. 16384."""
    value = _number(text, int)
    if not 16 <= value <= 16384:
        raise argparse.ArgumentTypeError(f"{value} px is not a usable image side; give 16 .. 16384 pixels")
    return value


def frame_index(text: str) -> int:
    """A 0-based frame index (>= 0)."""
    return int_at_least(0)(text)
