"""map_jobs: results in input order, one job and two jobs alike, worker state, failures naming the item."""

from __future__ import annotations

import os

import pytest

from broadtrack_graph.actions.parallel import JobError, map_jobs

_OFFSET = None


def _set_offset(offset: int) -> None:
    global _OFFSET
    _OFFSET = offset


def _square_plus_offset(item: int) -> tuple[int, int]:
    return item, item * item + _OFFSET


def _fail_on_seven(item: int) -> int:
    if item == 7:
        raise ValueError(f"seven is not allowed (pid {os.getpid()})")
    return item


def test_one_job_keeps_order_and_runs_the_initializer():
    seen = []
    out = map_jobs(_square_plus_offset, [3, 1, 2], 1, initializer=_set_offset, initargs=(10,), on_result=seen.append)
    assert out == [(3, 19), (1, 11), (2, 14)] and seen == out
    assert map_jobs(_square_plus_offset, [], 1, initializer=_set_offset, initargs=(0,)) == []


def test_two_jobs_give_the_same_results_in_input_order():
    items = list(range(23, -1, -1))  # more items than a pool chunk, in descending order
    one = map_jobs(_square_plus_offset, items, 1, initializer=_set_offset, initargs=(5,))
    seen = []
    two = map_jobs(_square_plus_offset, items, 2, initializer=_set_offset, initargs=(5,), on_result=seen.append)
    assert one == two == seen == [(i, i * i + 5) for i in items]


@pytest.mark.parametrize("jobs", [1, 2])
def test_a_failure_names_its_item(jobs):
    seen = []
    with pytest.raises(JobError, match=r"check: item 5 7 failed: ValueError: seven is not allowed") as info:
        map_jobs(_fail_on_seven, [1, 2, 3, 4, 5, 7, 8, 9], jobs, label="check", on_result=seen.append)
    assert (info.value.index, info.value.item) == (5, 7)
    assert isinstance(info.value.__cause__, ValueError)
    assert seen == [1, 2, 3, 4, 5]  # every item before the failing one was handed over, in order
