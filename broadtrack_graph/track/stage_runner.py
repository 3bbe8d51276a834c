"""The global search's stages, run in order, with the next ones started ahead on worker processes.

A shot whose camera is not known is searched through several stages (candidate focal points,
:mod:`~broadtrack_graph.track.search_stages`), each a weight-free search of the marking map of about
a second at 720p, and the policy reads their results in order until one ends the search
(:meth:`~broadtrack_graph.track.reinit_policy.ReinitPolicy.decide`). While this process computes the
stage the policy needs, worker processes compute the stages after it; a stage the policy never reads
is thrown away. The decision's other independent label-and-fit runs (a shot's guesses, a new camera tried
along its line of sight) go the same way once a search has started the workers (:meth:`StageRunner.mapped`).
The policy sees the same results in the same order as with no workers, so a run's
cameras do not depend on the number of workers, only its speed: the tracker runs in one process and
decodes ahead in a thread, so at a cut, while it searches, the machine's other cores are idle.

The search function must be a module-level function (it is sent to the workers by name); a search
that is not (a test's fake) runs in this process. The workers start when a search first reads past
its first stage, each taking the pitch and template once (pickled as their recipes: a few kB, so
starting them does not wait for their imports); a worker that dies leaves the rest of the run to
this process. The one other place that spreads work over processes is
:func:`broadtrack_graph.actions.parallel.map_jobs` (whole units of work).
"""

from __future__ import annotations

import logging
import multiprocessing
import os
import pickle
import signal
import sys
import threading
import time
from concurrent.futures import CancelledError, Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool
from pathlib import Path
from typing import Callable, Iterator, Sequence

log = logging.getLogger(__name__)

QUEUED_PER_WORKER = 2
"""Stages handed to each worker at a time: the one it computes and the next, so that it need not wait for this
process to hand it more (this process is busy with a stage of its own)."""

_WORKER_STATE: tuple | None = None  # in a worker: (search, pitch, curves, sampling)


def default_search_workers() -> int:
    """Worker processes by default: from the command line, every core but the tracker's own, at most 3 (a search
    has about 8 stages); called as a library, none.

    A worker process starts afresh and imports the program's main module (Python's "spawn"): a script that
    tracks at its top level, with no ``if __name__ == "__main__":`` guard, would run again in every worker. The
    command line is guarded; a script that is may set ``TrackingConfig.search_workers`` itself.
    """
    if not _main_is_command_line():
        return 0
    return max(0, min((os.cpu_count() or 1) - 1, 3))


def _main_is_command_line() -> bool:
    main = sys.modules.get("__main__")
    spec = getattr(main, "__spec__", None)
    if spec is not None:
        return spec.name == "broadtrack_graph.cli"
    return Path(getattr(main, "__file__", "") or "").name == "broadtrack-graph"


def _start_worker(search: Callable, pitch, curves, sampling, parent_pid: int) -> None:
    import cv2

    cv2.setNumThreads(1)  # one core per worker
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C stops the tracker, which stops its workers
    threading.Thread(target=_exit_with_parent, args=(parent_pid,), daemon=True).start()
    global _WORKER_STATE
    _WORKER_STATE = (search, pitch, curves, sampling)


def _exit_with_parent(parent_pid: int) -> None:
    """A worker whose tracker was killed (no shutdown) would wait for work forever: it leaves within a second."""
    while os.getppid() == parent_pid:
        time.sleep(1.0)
    os._exit(0)


def _run_stage(observations, detections, positions):
    search, pitch, curves, sampling = _WORKER_STATE
    return search(observations, detections, pitch, positions, curves, sampling)


def _run_call(function: Callable, args: tuple, keywords: dict):
    """One call of :meth:`StageRunner.mapped` in a worker, with the template it holds."""
    return function(*args, curves=_WORKER_STATE[2], **keywords)


def _warm() -> None:
    """Nothing: submitted once so that a worker starts (and imports the search) before it is needed."""


class StageRunner:
    """Runs a global search's stages, yielding their results in order (module docstring).

    Args:
        search: one global search, ``(observations, detections, pitch, positions, curves, sampling) -> ReinitResult``.
        workers: worker processes computing later stages ahead (0: every stage in this process).
    """

    def __init__(self, search: Callable, workers: int = 0) -> None:
        self.search = search
        self.workers = max(0, int(workers))
        self._pool: ProcessPoolExecutor | None = None
        self._bound: tuple | None = None  # the (pitch, curves, sampling) the workers hold
        self._disabled = self.workers == 0 or not _picklable(search)
        self.ahead = 0  # stages (and calls) computed by a worker that were read

    def results(self, stages: Sequence, observations, detections, pitch, curves, sampling) -> Iterator:
        """The result of each stage (its candidate positions) in order; stop reading to end the search.

        The stages after the one being read run ahead on the workers; whatever is not read is dropped.
        """
        def here(k):
            return self.search(observations, detections, pitch, stages[k], curves, sampling)

        def ahead(k):
            return self._pool.submit(_run_stage, observations, detections, stages[k])

        started = self._pool is not None
        pool = self._pool_for(pitch, curves, sampling) if started and len(stages) > 1 else None
        first = 0
        if not started and not self._disabled and len(stages) > 2:
            # The workers start when a search first reads past its first stage: a run whose cameras are found
            # at once never pays for starting them.
            yield here(0)
            first = 1
            pool = self._pool_for(pitch, curves, sampling)
        if pool is None:
            for k in range(first, len(stages)):
                yield here(k)
            return
        yield from self._in_order(len(stages), first, here, ahead)

    def mapped(self, function: Callable, calls: Sequence[tuple], curves, **keywords) -> Iterator:
        """``function(*args, curves=curves, **keywords)`` for each ``args`` of ``calls``, in order (the label-and-fit
        runs of a decision, say): the calls after the one being read run ahead on the workers when they are running
        and hold this template, and the function can be sent to them (module level); else all run here. The workers
        are started by a search only."""
        def here(k):
            return function(*calls[k], curves=curves, **keywords)

        def ahead(k):
            return self._pool.submit(_run_call, function, calls[k], keywords)

        if self._pool is None or len(calls) < 2 or self._bound[1] is not curves or not _picklable(function):
            for k in range(len(calls)):
                yield here(k)
            return
        yield from self._in_order(len(calls), 0, here, ahead)

    def _in_order(self, count: int, first: int, here: Callable, ahead: Callable) -> Iterator:
        """The results of tasks first .. count - 1 in order: the one needed now computed here (``here(k)``), the next
        ones handed to the workers (``ahead(k)`` -> Future); whatever is not read is dropped."""
        done: dict[int, object] = {}
        running: dict[int, Future] = {}
        claimed = first  # tasks [0, claimed) are done, or running here or on a worker

        def feed() -> None:
            nonlocal claimed
            while self._pool is not None and claimed < count and \
                    sum(not f.done() for f in running.values()) < QUEUED_PER_WORKER * self.workers:
                try:
                    running[claimed] = ahead(claimed)
                except (BrokenProcessPool, RuntimeError) as error:
                    self._lose_pool(error)
                    return
                claimed += 1

        try:
            for k in range(first, count):
                while k not in done:
                    if k == claimed:  # the task needed now, not started: here, with the next ones ahead
                        claimed += 1
                        feed()
                        done[k] = here(k)
                    elif k in running and (running[k].done() or claimed >= count or self._pool is None):
                        future = running.pop(k)
                        try:
                            done[k] = future.result()
                            self.ahead += 1
                        except (BrokenProcessPool, CancelledError) as error:
                            self._lose_pool(error)
                            done[k] = here(k)
                    elif k in running:  # a worker is on it: this process takes the next task meanwhile
                        j = claimed
                        claimed += 1
                        feed()
                        done[j] = here(j)
                yield done.pop(k)
        finally:
            for future in running.values():
                future.cancel()  # not started: dropped; running: its result is ignored

    def labelled_results(self, stages: Sequence, *frame) -> Iterator:
        """(label, result) of the (label, positions) stages in order; the stages not read are dropped."""
        results = self.results([positions for _, positions in stages], *frame)
        try:
            for label, _ in stages:
                yield label, next(results)
        finally:
            results.close()

    def close(self) -> None:
        """Stop the workers (the runner then searches in this process)."""
        if self._pool is not None:
            self._pool.shutdown(wait=True, cancel_futures=True)
            self._pool = None
        self._disabled = True

    def _pool_for(self, pitch, curves, sampling) -> ProcessPoolExecutor | None:
        if self._disabled:
            return None
        if self._pool is None:
            try:
                context = multiprocessing.get_context("spawn")  # the tracker has threads: no fork
                self._pool = ProcessPoolExecutor(self.workers, mp_context=context, initializer=_start_worker,
                                                 initargs=(self.search, pitch, curves, sampling, os.getpid()))
                for _ in range(self.workers):
                    self._pool.submit(_warm)
            except (OSError, RuntimeError, pickle.PicklingError) as error:
                self._lose_pool(error)
                return None
            self._bound = (pitch, curves, sampling)
        if any(a is not b for a, b in zip(self._bound, (pitch, curves, sampling))):
            return None  # another template than the workers hold: this search runs here
        return self._pool

    def _lose_pool(self, error: BaseException) -> None:
        log.warning("search workers stopped (%s): searching in this process from now on", error)
        if self._pool is not None:
            self._pool.shutdown(wait=False, cancel_futures=True)
        self._pool, self._disabled = None, True


def _picklable(function: Callable) -> bool:
    try:
        pickle.dumps(function)
        return True
    except (pickle.PicklingError, AttributeError, TypeError):
        return False
