"""Which frames of a detections file a run uses: bounded by the clip, or by a sane gap, the rest reported.

A detections file names its frames itself, so one stray number (a timestamp written as a
frame, say 10000000) would otherwise make the run walk every frame up to it. With the
frames given, records outside the clip's frame window are dropped; without them, the file's
frames are split where two consecutive numbers are more than ``max_gap`` apart and only the
largest group is kept. Either way, one warning names what was dropped.
"""

from __future__ import annotations

import logging

import numpy as np

from broadtrack_graph.io.detections import DetectionsFile

log = logging.getLogger(__name__)

DEFAULT_MAX_GAP = 750  # frames (30 s at 25 fps): a larger jump between a file's frame numbers is not one clip


def _drop(detections: DetectionsFile, dropped: list[int]) -> None:
    for index in dropped:
        detections.frames.pop(index, None)
        detections.frame_ids.pop(index, None)
        detections.mask_paths.pop(index, None)


def _describe(dropped: list[int]) -> str:
    shown = ", ".join(str(i) for i in dropped[:3]) + (" ..." if len(dropped) > 3 else "")
    return f"{len(dropped)} record(s) (frame {shown})"


def bound_to_window(detections: DetectionsFile, start: int, end: int, where: str = "detections file") -> list[int]:
    """Drop the records outside frames [start, end) (the clip given with the detections); returns them, sorted."""
    dropped = sorted(i for i in detections.frames if not start <= i < end)
    if dropped:
        _drop(detections, dropped)
        log.warning("%s: %s outside the frames %d..%d of the clip dropped", where, _describe(dropped), start, end - 1)
    return dropped


def bound_by_gap(detections: DetectionsFile, max_gap: int = DEFAULT_MAX_GAP, where: str = "detections file") -> list[int]:
    """Keep the largest group of frame numbers no more than ``max_gap`` apart; drop (and report) the rest.

    Returns:
        the dropped frame indices, sorted.
    """
    indices = np.array(sorted(detections.frames), dtype=np.int64)
    if len(indices) < 2:
        return []
    breaks = np.nonzero(np.diff(indices) > max_gap)[0]
    if not len(breaks):
        return []
    groups = np.split(indices, breaks + 1)
    keep = max(groups, key=len)  # ties: the earliest
    dropped = sorted(int(i) for group in groups if group is not keep for i in group)
    _drop(detections, dropped)
    log.warning("%s: %s more than %d frames away from the other %d records dropped (a stray frame number?)",
                where, _describe(dropped), max_gap, len(keep))
    return dropped
