"""Cut a long clip into overlapping windows that can run in parallel, and stitch their results back.

Pure functions (no I/O). A :class:`Chunk` owns the frames ``[keep_lo, keep_hi)`` of the clip and
is solved over the wider window ``[lo, hi)`` (``overlap`` frames more on each side, where the
clip has them) so that its kept frames do not sit at a window edge. The kept ranges partition
the clip: stitching takes every frame from exactly one chunk. A shot list (frame ranges of
camera cuts) can replace the regular cut: :func:`chunks_from_ranges`.
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Chunk:
    """One window of a clip, frame indices absolute in the input (end exclusive)."""

    index: int  # position in the plan
    lo: int  # first frame solved
    hi: int  # end of the frames solved
    keep_lo: int  # first frame this chunk contributes
    keep_hi: int  # end of the frames it contributes

    def as_dict(self) -> dict:
        return dict(self.__dict__)


def plan_chunks(start: int, end: int, chunk_frames: int, overlap: int) -> list[Chunk]:
    """Regular chunks of ``chunk_frames`` kept frames over ``[start, end)``, windows widened by ``overlap``.

    A last piece shorter than a quarter chunk is merged into the one before it.

    Raises:
        ValueError: an empty range, chunk_frames < 1 or overlap < 0.
    """
    if end <= start or chunk_frames < 1 or overlap < 0:
        raise ValueError(f"cannot cut [{start}, {end}) into chunks of {chunk_frames} (overlap {overlap})")
    cuts = list(range(start, end, chunk_frames)) + [end]
    if len(cuts) > 2 and cuts[-1] - cuts[-2] < max(1, chunk_frames // 4):
        del cuts[-2]
    return chunks_from_ranges(list(zip(cuts[:-1], cuts[1:])), start, end, overlap)


def chunks_from_ranges(ranges: list[tuple[int, int]], start: int, end: int, overlap: int) -> list[Chunk]:
    """Chunks keeping the given consecutive ranges (e.g. shots), windows widened by ``overlap`` within [start, end).

    Raises:
        ValueError: the ranges do not tile ``[start, end)`` without gaps or overlaps.
    """
    position = start
    for lo, hi in ranges:
        if lo != position or hi <= lo:
            raise ValueError(f"ranges must tile [{start}, {end}) in order; got [{lo}, {hi}) at frame {position}")
        position = hi
    if position != end:
        raise ValueError(f"ranges end at {position}, the clip at {end}")
    return [Chunk(n, max(start, lo - overlap), min(end, hi + overlap), lo, hi) for n, (lo, hi) in enumerate(ranges)]


def stitch(pieces: list[tuple[Chunk, list]], frame_of=lambda item: item.frame_index) -> list:
    """Items of every chunk's kept range, in frame order; each frame exactly once.

    Args:
        pieces: (chunk, its items) per chunk; items carry a frame index (``frame_of``).

    Raises:
        ValueError: a frame is given twice or the chunks' kept ranges are not consecutive.
    """
    out, seen = [], set()
    ordered = sorted(pieces, key=lambda piece: piece[0].keep_lo)
    for (before, _), (after, _) in zip(ordered[:-1], ordered[1:]):
        if before.keep_hi != after.keep_lo:
            raise ValueError(f"chunks {before.index} and {after.index} leave a gap or overlap at frame {before.keep_hi}")
    for chunk, items in ordered:
        for item in items:
            frame = frame_of(item)
            if chunk.keep_lo <= frame < chunk.keep_hi:
                if frame in seen:
                    raise ValueError(f"frame {frame} appears twice in chunk {chunk.index}")
                seen.add(frame)
                out.append(item)
    return sorted(out, key=frame_of)
