"""Iterate in a background thread: decoding and preparing frames overlap the caller's work."""

from __future__ import annotations


def prefetch(iterable, transform=None, depth: int = 4):
    """Iterate in a background thread (decoding, preparing) while the caller works on the previous items.

    OpenCV releases the GIL, so image decoding and pyramid building overlap the solver on the
    second core. Exceptions of the producer are raised in the consumer.
    """
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
