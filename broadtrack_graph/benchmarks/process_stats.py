"""Per-frame time and memory of a tracking run in this process: RSS / peak RSS from /proc and a
clock hooked on ``TrackingRun.process`` (wall and CPU milliseconds per frame, RSS samples).
"""

from __future__ import annotations

import time
from array import array

RSS_EVERY_FRAMES = 100
"""The process RSS is sampled every this many frames (and at the end of every block)."""


def rss_mb() -> float | None:
    """Resident set size of this process in MB (VmRSS of /proc/self/status; None where there is none)."""
    try:
        with open("/proc/self/status", encoding="ascii") as handle:
            for line in handle:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    return None


def peak_rss_mb() -> float | None:
    """Peak resident set size of this process in MB (ru_maxrss, kilobytes on Linux)."""
    try:
        import resource

        return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
    except (ImportError, OSError):
        return None


class FrameClock:
    """Times every ``TrackingRun.process`` call and samples the RSS (wraps the run's method).

    Attributes (arrays, one entry per processed frame, in order):
        process_ms: wall time of the call; cpu_ms: CPU time of the calling thread during it;
        interval_ms: wall time since the previous call ended (the first: since wrapping).
        rss: (frames processed, MB) samples, every ``rss_every`` frames, at the end of every
            ``block`` frames and (:meth:`sample_rss`) when the caller asks.
    """

    def __init__(self, run, rss_every: int = RSS_EVERY_FRAMES, block: int | None = None) -> None:
        # array('d'): 8 bytes a value, so the bookkeeping adds < 0.1 MB per 1000 frames to the RSS it measures.
        self.process_ms = array("d")
        self.cpu_ms = array("d")
        self.interval_ms = array("d")
        self.rss: list[tuple[int, float]] = []
        self.rss_every = max(1, int(rss_every))
        self.block = None if block is None else max(1, int(block))
        self._inner = run.process
        self._last_end = time.perf_counter()
        first = rss_mb()
        if first is not None:
            self.rss.append((0, first))
        run.process = self  # run_loop calls run.process(frame)

    def __call__(self, frame) -> None:
        wall0, cpu0 = time.perf_counter(), time.thread_time()
        try:
            self._inner(frame)
        finally:
            wall1, cpu1 = time.perf_counter(), time.thread_time()
            self.process_ms.append(1000.0 * (wall1 - wall0))
            self.cpu_ms.append(1000.0 * (cpu1 - cpu0))
            self.interval_ms.append(1000.0 * (wall1 - self._last_end))
            self._last_end = wall1
            count = len(self.process_ms)
            if count % self.rss_every == 0 or (self.block is not None and count % self.block == 0):
                self.sample_rss()

    def sample_rss(self) -> None:
        """Record the RSS now, against the number of frames processed so far (once per count)."""
        count = len(self.process_ms)
        value = rss_mb()
        if value is not None and (not self.rss or self.rss[-1][0] != count):
            self.rss.append((count, value))
