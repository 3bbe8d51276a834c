"""Iterate in a background thread: decoding and preparing frames overlap the caller's work."""

from __future__ import annotations

import os

PREFETCH_ENV = "BROADTRACK_PREFETCH"
"""Environment variable: "0" turns the background thread off (items are made in the caller's thread).
``track-many`` sets it on its workers when they fill every core: there the thread has no idle core
to run on and only competes with the other workers."""


def prefetch(iterable, transform=None, depth: int = 4):
    """Iterate in a background thread (decoding, preparing) while the caller works on the previous items.

    OpenCV releases the GIL, so image decoding and pyramid building overlap the solver on the
    second core. Exceptions of the producer are raised in the consumer. With the environment
    variable :data:`PREFETCH_ENV` set to "0", the same items come from the caller's thread.
    """
    if os.environ.get(PREFETCH_ENV) == "0":
        yield from (transform(item) if transform else item for item in iterable)
        return
    import queue
    import threading

    items: queue.Queue = queue.Queue(maxsize=depth)
    done = object()
    stop = threading.Event()

    def produce():
        try:
            for item in iterable:
                if stop.is_set():
                    break
                items.put(transform(item) if transform else item)
        except BaseException as exc:  # handed to the consumer
            items.put(exc)
        finally:
            items.put(done)

    thread = threading.Thread(target=produce, name="prefetch", daemon=True)
    thread.start()
    try:
        while True:
            item = items.get()
            if item is done:
                return
            if isinstance(item, BaseException):
                raise item
            yield item
    finally:
        stop.set()
        while thread.is_alive():
            try:
                items.get_nowait()
            except Exception:
                thread.join(timeout=0.05)
