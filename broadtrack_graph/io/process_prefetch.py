"""Iterate in a process of its own: items made in a spawned child process, their arrays handed over through shared
memory.

Threads of one process contend for the interpreter's lock: the decoding thread's Python steps and the tracking
thread's take turns, and on two cores the work of both costs a fifth more than done in one thread. A child process
has an interpreter of its own. What it makes is pickled (protocol 5) with its contiguous arrays out of band; the
arrays are copied into one of ``depth`` shared-memory slots and the small rest goes through a queue; the consumer
copies the arrays out of the slot (a few milliseconds for a 1920x1080 frame and its maps), frees the slot and
rebuilds the item. The slots bound how far the child runs ahead.

The child is started with ``spawn`` (a fork would copy the parent's threads and open video readers into a process
that cannot run them), so the producer must be picklable: a function of an importable module (not the script run as
``__main__``), or a ``functools.partial`` of one, called in the child with a function that says how many items the
consumer has taken so far. The child does not run the consumer's main script again (``spawn`` would, as
``__mp_main__``: a script that tracks a clip at its top level, with no ``if __name__ == "__main__"`` guard, would
track it again in the child). Whatever the producer's
generator returns is :attr:`ProcessPrefetch.result` once the iteration ends. The child's log records are emitted
by the consumer's loggers; an exception in the child is raised in the consumer; a child that dies without one is
reported in one line. The child ignores Ctrl-C (the consumer handles it and stops the child) and stops by itself
when the consumer's process is gone.
"""

from __future__ import annotations

import contextlib
import logging
import os
import pickle
import queue
import resource
import signal
import sys
import time
import types
from multiprocessing import get_context
from multiprocessing.shared_memory import SharedMemory
from typing import Callable, Iterator

Producer = Callable[[Callable[[], int]], Iterator]
"""Called in the child with ``taken`` (the number of items the consumer has taken so far); returns the items."""

SLOT_BYTES = 16 * 1024 * 1024
"""The size of a shared-memory slot (bytes). An item whose arrays do not fit goes through the queue, pickled whole
(slower, but the same item)."""

_POLL_S = 0.5
"""How often a blocked side checks that the other is still there (seconds)."""


def cpu_seconds() -> float:
    """CPU seconds of this process (every thread) and of its child processes that have ended and been waited for
    (a :class:`ProcessPrefetch` child is, once its iteration ends): what a run cost the machine."""
    children = resource.getrusage(resource.RUSAGE_CHILDREN)
    return time.process_time() + children.ru_utime + children.ru_stime


class ProcessPrefetch:
    """Iterate a producer's items made ahead in a spawned child process (see the module docstring).

    Args:
        producer: a picklable ``taken -> iterator`` (:data:`Producer`).
        depth: the shared-memory slots: how many items the child may have made that the consumer has not taken.
        slot_bytes: the size of a slot.
        name: the child process's name (in ``ps`` and in error messages).
    """

    def __init__(self, producer: Producer, depth: int = 4, slot_bytes: int = SLOT_BYTES,
                 name: str = "prefetch") -> None:
        self.producer = producer
        self.depth = max(1, int(depth))
        self.slot_bytes = int(slot_bytes)
        self.name = name
        self.result = None

    def __iter__(self) -> Iterator:
        context = get_context("spawn")
        messages = context.Queue()
        free = context.Queue()
        taken = context.Value("q", 0, lock=False)
        slots = [SharedMemory(create=True, size=self.slot_bytes) for _ in range(self.depth)]
        for k in range(self.depth):
            free.put(k)
        child = context.Process(target=_child_main, name=self.name, daemon=True,
                                args=(self.producer, [s.name for s in slots], messages, free, taken, os.getpid(),
                                      logging.getLogger().getEffectiveLevel()))
        with _main_script_hidden():
            child.start()
        try:
            while True:
                kind, payload = _next_message(messages, child, self.name)
                if kind == "item":
                    header, slot, spans = payload
                    # Copied out (no view of the slot outlives this line): the slot is free again.
                    buffers = [bytearray(slots[slot].buf[start:stop]) for start, stop in spans]
                    free.put(slot)
                    item = pickle.loads(header, buffers=buffers)
                elif kind == "whole":
                    item = pickle.loads(payload)
                elif kind == "log":
                    logging.getLogger(payload.name).handle(payload)
                    continue
                elif kind == "error":
                    raise payload
                else:  # "done"
                    self.result = payload
                    return
                taken.value += 1
                yield item
        finally:
            if child.is_alive():
                child.terminate()
            child.join(timeout=5)
            for shared in slots:
                shared.close()
                shared.unlink()
            messages.close()
            free.close()


@contextlib.contextmanager
def _main_script_hidden():
    """While a child is started: the main module replaced by an empty one, so that the child is not told to run the
    consumer's main script again (what ``spawn`` sends it is read from ``sys.modules["__main__"]``)."""
    main = sys.modules.get("__main__")
    sys.modules["__main__"] = types.ModuleType("__main__")
    try:
        yield
    finally:
        if main is not None:
            sys.modules["__main__"] = main


def _next_message(messages, child, name: str):
    """The child's next message; raises RuntimeError when the child died without saying why."""
    while True:
        try:
            return messages.get(timeout=_POLL_S)
        except queue.Empty:
            if not child.is_alive():
                try:  # its last words may have come in just before it ended
                    return messages.get(timeout=_POLL_S)
                except queue.Empty:
                    raise RuntimeError(f"the {name} process ended without a result (exit code {child.exitcode})") \
                        from None


class _QueueLogHandler(logging.Handler):
    """Sends the child's log records to the consumer (their message formatted here: the arguments may not pickle)."""

    def __init__(self, messages) -> None:
        super().__init__()
        self.messages = messages

    def emit(self, record: logging.LogRecord) -> None:
        try:
            record.msg, record.args = record.getMessage(), None
            record.exc_info, record.exc_text = None, None
            self.messages.put(("log", record))
        except Exception:  # a log line is never worth the run
            pass


def _child_main(producer: Producer, slot_names: list[str], messages, free, taken, parent_pid: int,
                log_level: int) -> None:
    """The child process: make the items and hand them over (see the module docstring)."""
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # Ctrl-C is the consumer's to handle
    root = logging.getLogger()
    root.handlers[:] = [_QueueLogHandler(messages)]
    root.setLevel(log_level)
    slots = [SharedMemory(name=name) for name in slot_names]
    try:
        items = iter(producer(lambda: taken.value))
        while True:
            try:
                item = next(items)
            except StopIteration as stop:
                messages.put(("done", stop.value))
                return
            buffers: list = []
            header = pickle.dumps(item, protocol=5, buffer_callback=buffers.append)
            raws = [b.raw() for b in buffers]
            if sum(r.nbytes for r in raws) > len(slots[0].buf):
                messages.put(("whole", pickle.dumps(item, protocol=5)))
                continue
            slot = _free_slot(free, parent_pid)
            spans, start = [], 0
            for raw in raws:
                slots[slot].buf[start:start + raw.nbytes] = raw
                spans.append((start, start + raw.nbytes))
                start += raw.nbytes
            messages.put(("item", (header, slot, spans)))
    except BaseException as exc:  # handed to the consumer
        messages.put(("error", picklable_exception(exc)))
    finally:
        for shared in slots:
            shared.close()
        messages.close()
        messages.join_thread()


def _free_slot(free, parent_pid: int) -> int:
    """A free slot (waits while the consumer holds them all); exits when the consumer's process is gone."""
    while True:
        try:
            return free.get(timeout=_POLL_S)
        except queue.Empty:
            if os.getppid() != parent_pid:
                raise SystemExit(0)


def picklable_exception(exc: BaseException) -> BaseException:
    """The exception itself when it survives pickling (out and back in), else a RuntimeError with its type and text:
    what a worker process hands its caller."""
    try:
        pickle.loads(pickle.dumps(exc))
        return exc
    except Exception:
        return RuntimeError(f"{type(exc).__name__}: {exc}")

