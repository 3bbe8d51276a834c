"""The frames fed to a tracking run: decoded, and prepared ahead while the run tracks.

:func:`run_loop` feeds a :class:`~broadtrack_graph.track.frame_loop.TrackingRun` the frames of an iterable,
prepared ahead (:class:`~broadtrack_graph.track.ahead.FramesAhead`: the repeat test, the flow pyramid, the camera-free
half of detection, the flow while there is time) by a background thread
(:func:`~broadtrack_graph.io.prefetch.prefetch`), or taken as they come when a process of their own prepared them
(:class:`~broadtrack_graph.track.ahead.FramesInProcess`). The result is the same as doing it all in the tracking
thread (``BROADTRACK_PREFETCH=0`` does). The progress bar and an interruption (Ctrl-C, SIGTERM) are handled here.
Both threads call OpenCV: a run is given :func:`default_opencv_threads` threads of OpenCV's own (``track
--threads``; ``bench real`` times its runs with the same).
"""

from __future__ import annotations

import os

from tqdm import tqdm

from broadtrack_graph.io.prefetch import prefetch
from broadtrack_graph.track.ahead import FramesAhead
from broadtrack_graph.track.frame_loop import TrackingRun


def default_opencv_threads() -> int:
    """OpenCV's threads for a run: the cores its tracking and decoding threads leave, at least 1.

    Both threads call OpenCV, and each of the search's workers runs it on one thread: a pool on top of them only
    oversubscribes the cores. On 2 cores, the splice of docs/BENCHMARKS.md tracked with OpenCV's default pool (a
    thread per core) spent twice the time in the kernel for the same cameras.
    """
    return max(1, (os.cpu_count() or 1) - 2)


def run_loop(run: TrackingRun, frames, total: int | None = None, label: str = "") -> None:
    """Feed frames to a run (prefetching them in a background thread), with a progress bar unless the run's context
    hides it (``total``: the frames expected, for the bar; ``label``: the bar's)."""
    progress = run.context.progress
    taken = [0]  # frames taken by the loop
    if getattr(frames, "prepared_ahead", False):
        ready = iter(frames)  # prepared where they were made (a process of their own)
    else:
        ahead = FramesAhead(run.config, getattr(run.detector, "find_markings", None), lambda: taken[0])
        ready = prefetch(frames, ahead)
    bar = tqdm(ready, total=total, desc=f"track {label}", unit="frame", disable=not progress)
    try:
        for frame in bar:
            taken[0] += 1
            run.process(frame)
            if progress:
                bar.set_postfix(run.writer.progress_postfix() if hasattr(run.writer, "progress_postfix") else {},
                                refresh=False)
    except KeyboardInterrupt:
        # Ctrl-C or SIGTERM (the command line turns it into KeyboardInterrupt): the summary tells the truth.
        if hasattr(run.writer, "interrupt"):
            run.writer.interrupt()
        raise
    finally:
        bar.close()
