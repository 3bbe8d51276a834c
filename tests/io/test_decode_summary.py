"""One summary line for an undecodable video tail (broadtrack_graph.io.decode_summary)."""

from __future__ import annotations

import logging
from dataclasses import dataclass

from broadtrack_graph.io.decode_summary import drop_undecodable_tail
from broadtrack_graph.io.video import logger as video_logger

BAD = "video frame cannot be decoded"


@dataclass
class F:
    frame_index: int
    problem: str | None = None


def test_the_tail_is_dropped_with_one_line_and_gaps_are_kept(caplog):
    frames = [F(0), F(1, BAD), F(2)] + [F(i, BAD) for i in range(3, 10)]
    source_log = video_logger  # the video source's own logger: its per-frame lines are counted, not shown

    def source():
        for frame in frames:
            if frame.problem:
                source_log.warning("clip.mp4: frame %d: %s; marked missing", frame.frame_index, frame.problem)
            yield frame

    with caplog.at_level(logging.WARNING):
        out = list(drop_undecodable_tail(source(), "clip.mp4", 12))
    assert [f.frame_index for f in out] == [0, 1, 2]
    lines = [r.getMessage() for r in caplog.records]
    assert lines == ["clip.mp4: 1 frame(s) from frame 1 cannot be decoded; marked missing",
                     "clip.mp4: the container states 12 frames, 3 decode; the rest is not read"]
