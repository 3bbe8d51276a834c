"""Items made in a spawned process and handed over through shared memory: the same items, the producer's result,
its errors and log lines, and nothing left behind when the consumer stops early."""

import functools
import logging
import os
import time
from pathlib import Path

import numpy as np
import pytest

from broadtrack_graph.errors import InputError
from broadtrack_graph.io.process_prefetch import ProcessPrefetch, cpu_seconds

SHM_DIR = Path("/dev/shm")


def numbered_arrays(count: int, side: int, taken):
    """Items with arrays of several kinds; returns what the producer saw of the consumer's progress."""
    seen = []
    for k in range(count):
        seen.append(taken())
        yield {"index": k, "image": np.full((side, side, 3), k, np.uint8), "mask": np.eye(side, dtype=bool),
               "points": np.arange(6.0).reshape(3, 2) + k, "note": f"item {k}"}
    return {"count": count, "taken_seen": seen}


def failing(taken):
    yield 1
    raise InputError("clip.mp4", "frame 1 cannot be decoded")


def logging_producer(taken):
    logging.getLogger("broadtrack_graph.tests.child").warning("from the child: %d frames", 3)
    yield 1


def busy(seconds: float, taken):
    started = time.process_time()
    while time.process_time() - started < seconds:
        sum(range(1000))
    yield 1


def dying(taken):
    yield 1
    os._exit(3)


def shared_segments() -> set:
    return {p.name for p in SHM_DIR.glob("psm_*")} if SHM_DIR.is_dir() else set()


def test_items_arrive_whole_in_order_with_the_producers_result():
    feed = ProcessPrefetch(functools.partial(numbered_arrays, 12, 64), depth=3)
    items = list(feed)
    assert [item["index"] for item in items] == list(range(12))
    for k, item in enumerate(items):
        assert item["image"].shape == (64, 64, 3) and (item["image"] == k).all()
        assert item["image"].flags.writeable  # the consumer owns it
        assert np.array_equal(item["mask"], np.eye(64, dtype=bool))
        assert np.array_equal(item["points"], np.arange(6.0).reshape(3, 2) + k)
        assert item["note"] == f"item {k}"
    assert feed.result["count"] == 12
    assert max(feed.result["taken_seen"]) <= 12  # the consumer's count reaches the producer
    assert feed.result["taken_seen"] == sorted(feed.result["taken_seen"])


def test_an_item_larger_than_a_slot_is_sent_whole():
    items = list(ProcessPrefetch(functools.partial(numbered_arrays, 3, 128), depth=2, slot_bytes=4096))
    assert [int(item["image"][0, 0, 0]) for item in items] == [0, 1, 2]


def test_an_error_in_the_producer_is_raised_in_the_consumer_as_it_was():
    feed = ProcessPrefetch(failing)
    got = []
    with pytest.raises(InputError) as raised:
        for item in feed:
            got.append(item)
    assert got == [1]
    assert str(raised.value) == "clip.mp4: frame 1 cannot be decoded"
    assert raised.value.problem == "frame 1 cannot be decoded"


def test_the_producers_log_lines_are_the_consumers(caplog):
    with caplog.at_level(logging.WARNING):
        assert list(ProcessPrefetch(logging_producer)) == [1]
    assert "from the child: 3 frames" in caplog.text


def test_a_producer_that_dies_is_reported_in_one_line():
    with pytest.raises(RuntimeError, match=r"the prefetch process ended without a result \(exit code 3\)"):
        list(ProcessPrefetch(dying))


def test_stopping_early_stops_the_child_and_frees_the_shared_memory():
    before = shared_segments()
    feed = ProcessPrefetch(functools.partial(numbered_arrays, 1000, 256), depth=2)
    for item in feed:
        if item["index"] == 2:
            break
    assert shared_segments() <= before


def test_the_child_does_not_run_the_consumers_main_script_again(tmp_path):
    import subprocess
    import sys

    (tmp_path / "helper_producer.py").write_text("def three(taken):\n    yield from (1, 2, 3)\n")
    marker = tmp_path / "ran.txt"
    script = tmp_path / "unguarded.py"
    script.write_text(
        "import helper_producer\n"
        "from broadtrack_graph.io.process_prefetch import ProcessPrefetch, cpu_seconds\n"
        f"with open({str(marker)!r}, 'a') as f:\n"
        "    f.write('ran\\n')\n"  # top level, no __main__ guard: what a quick script does
        "print(list(ProcessPrefetch(helper_producer.three)))\n")
    done = subprocess.run([sys.executable, str(script)], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "[1, 2, 3]"
    assert marker.read_text() == "ran\n"  # once: in the consumer only


def test_the_cpu_of_a_run_includes_the_childs_once_it_ended():
    before, own = cpu_seconds(), time.process_time()
    assert list(ProcessPrefetch(functools.partial(busy, 0.3))) == [1]
    assert cpu_seconds() - before >= 0.3 + (time.process_time() - own)
