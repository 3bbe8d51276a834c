"""Map one job over many items (clips, frames, pieces): a process pool, or a plain loop for one job.

:func:`map_jobs` is the one place where whole items of work are spread over processes; its signature
names no engine (a distributed engine can replace the body). Results come back in input order.
"""

from __future__ import annotations

import functools
import os
from collections.abc import Callable, Iterable
from concurrent.futures import ProcessPoolExecutor

from broadtrack_graph.io.process_prefetch import picklable_exception

POOL_CHUNK_ITEMS = 4
"""Items a pool worker takes at a time (fewer round trips; the order of results is unaffected)."""


class JobError(RuntimeError):
    """A job failed on one item; the message names the item, ``__cause__`` is the worker's exception.

    index: position of the item in the input; item: the item itself.
    """

    def __init__(self, label: str, index: int, item, cause: BaseException) -> None:
        self.index, self.item = index, item
        shown = repr(item)
        shown = shown if len(shown) <= 80 else shown[:77] + "..."
        super().__init__(f"{label or 'job'}: item {index} {shown} failed: {type(cause).__name__}: {cause}")


def map_jobs(
    function: Callable,
    items: Iterable,
    jobs: int = 1,
    initializer: Callable | None = None,
    initargs: tuple = (),
    label: str = "",
    progress: bool = False,
    on_result: Callable | None = None,
) -> list:
    """``[function(item) for item in items]``, over ``jobs`` worker processes when jobs > 1.

    Args:
        function: a module-level function of one item (picklable for jobs > 1).
        items: the items; each is handed to ``function`` as is.
        jobs: worker processes; 1 runs everything in this process (more than the machine's
            cores are not started).
        initializer, initargs: run once per worker before its first item (state the workers
            share, e.g. a calibrator built once); with jobs = 1 once in this process.
        label: name of the job, for the progress bar and errors.
        progress: show a tqdm bar.
        on_result: called with each result in input order as soon as it is there (e.g.
            writing a file per item while later items still run).

    Returns:
        The results, in the order of ``items``.

    Raises:
        JobError: ``function`` raised on an item (the message names the item and its index).
    """
    from tqdm import tqdm

    items = list(items)
    jobs = max(1, min(int(jobs), os.cpu_count() or 1))
    results = []
    bar = tqdm(total=len(items), desc=label or None, unit="item", disable=not progress)

    def collect(outcomes) -> None:
        for index, (item, (ok, value)) in enumerate(zip(items, outcomes)):
            if not ok:
                raise JobError(label, index, item, value) from value
            bar.update(1)
            if on_result is not None:
                on_result(value)
            results.append(value)

    try:
        if jobs == 1:
            if initializer is not None:
                initializer(*initargs)
            collect(_guarded(function, item) for item in items)
        else:
            with ProcessPoolExecutor(jobs, initializer=initializer, initargs=initargs) as pool:
                collect(pool.map(functools.partial(_guarded, function), items, chunksize=POOL_CHUNK_ITEMS))
    finally:
        bar.close()
    return results


def _guarded(function: Callable, item) -> tuple[bool, object]:
    """(True, result) or (False, the exception), so that a failure is tied to its own item."""
    try:
        return True, function(item)
    except Exception as exc:  # noqa: BLE001 -- handed to the caller as a JobError naming the item
        return False, picklable_exception(exc)  # one that cannot cross processes: a RuntimeError with its text


class SerialEngine:
    """The engine interface of track-many run in this process, one call after the other.

    An engine runs ``function(*args)`` for each call and reports each outcome as it comes:
    ``on_done(key, result)`` or, after ``retries`` more attempts, ``on_error(key, message)``
    with a one-line message. :class:`~broadtrack_graph.actions.ray_engine.RayEngine` is the
    distributed one; this one is the one-process reference (and what tests use without Ray).
    """

    name = "serial"
    workers = 1

    def __init__(self, retries: int = 0) -> None:
        self.retries = max(0, int(retries))

    def __enter__(self) -> "SerialEngine":
        return self

    def __exit__(self, *exc) -> None:
        return None

    def run(self, function: Callable, calls: list[tuple[object, tuple]], on_done: Callable, on_error: Callable) -> None:
        """calls: (key, args) pairs; the key identifies the call in the callbacks."""
        for key, args in calls:
            for attempt in range(self.retries + 1):
                try:
                    result = function(*args)
                except Exception as exc:  # noqa: BLE001 -- reported per call, the others go on
                    if attempt == self.retries:
                        on_error(key, one_line(exc))
                    continue
                on_done(key, result)
                break


def one_line(exc: BaseException) -> str:
    """``Type: message`` of an exception on one line (the first line of its message)."""
    text = str(exc).strip().splitlines()
    return f"{type(exc).__name__}: {text[0] if text else ''}".rstrip(": ")
