"""Prefetching in a background thread (broadtrack_graph.io.prefetch), and its switch."""

from __future__ import annotations

import threading

import pytest

from broadtrack_graph.io.prefetch import PREFETCH_ENV, prefetch


def _threads_of(monkeypatch, value):
    if value is None:
        monkeypatch.delenv(PREFETCH_ENV, raising=False)
    else:
        monkeypatch.setenv(PREFETCH_ENV, value)
    seen = []

    def transform(item):
        seen.append(threading.current_thread().name)
        return item * 10

    assert list(prefetch(range(5), transform)) == [0, 10, 20, 30, 40]
    return set(seen)


def test_items_are_made_in_a_background_thread_unless_switched_off(monkeypatch):
    assert _threads_of(monkeypatch, None) == {"prefetch"}
    assert _threads_of(monkeypatch, "0") == {threading.current_thread().name}


def test_a_producer_error_reaches_the_consumer():
    def broken():
        yield 1
        raise ValueError("frame 2 is corrupt")

    with pytest.raises(ValueError, match="corrupt"):
        list(prefetch(broken()))
