"""One summary line for a video whose container announces more frames than it holds.

Containers often state a frame count larger than what decodes (the FA Cup clip claims 398
and holds ~380). :func:`drop_undecodable_tail` wraps a frame source's iteration: frames the
decoder fails on are held back while they run on; if a readable frame follows they are
passed on (a real gap, the tracker marks them missing), if the stream ends they are dropped
and ONE line is logged naming the file, the stated and the decoded counts. While it runs,
the source's own per-frame "cannot be decoded" warnings are filtered out of the log (they
are counted into the summary instead).
"""

from __future__ import annotations

import logging
from typing import Iterable, Iterator

from broadtrack_graph.io.video import logger as video_logger

log = logging.getLogger(__name__)
_PER_FRAME_MARKERS = ("cannot be decoded; marked missing", "video ended at frame")


class _PerFrameDecodeWarnings(logging.Filter):
    """Drops the frame source's per-frame decoding warnings (counted instead)."""

    def __init__(self) -> None:
        super().__init__()
        self.dropped = 0

    def filter(self, record: logging.LogRecord) -> bool:
        message = record.getMessage()
        if any(marker in message for marker in _PER_FRAME_MARKERS):
            self.dropped += 1
            return False
        return True


def decodable_frames(source: Iterable) -> Iterable:
    """A frame source's frames; a video's through :func:`drop_undecodable_tail` (other sources as they are)."""
    if getattr(source, "kind", None) != "video":
        return source
    return drop_undecodable_tail(source, str(getattr(source, "path", "video")), len(source))


def drop_undecodable_tail(frames: Iterable, name: str, stated_frames: int | None = None) -> Iterator:
    """Yield ``frames`` (objects with ``frame_index`` and ``problem``), without an undecodable tail.

    Args:
        frames: a frame source or any iterable of its frames, in order.
        name: the input's name for the summary line (its path).
        stated_frames: the frame count the container states, or None.
    """
    held = []
    last_good = -1
    filter_ = _PerFrameDecodeWarnings()
    source_logger = video_logger
    source_logger.addFilter(filter_)
    try:
        for frame in frames:
            if getattr(frame, "problem", None) == "video frame cannot be decoded":
                held.append(frame)
                continue
            if held:
                log.warning("%s: %d frame(s) from frame %d cannot be decoded; marked missing", name, len(held),
                            held[0].frame_index)
                yield from held
                held = []
            last_good = frame.frame_index
            yield frame
    finally:
        source_logger.removeFilter(filter_)
    if held or (stated_frames is not None and last_good + 1 < stated_frames):
        stated = f"states {stated_frames} frames" if stated_frames is not None else "states more frames"
        log.warning("%s: the container %s, %d decode; the rest is not read", name, stated, last_good + 1)
