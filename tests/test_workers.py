"""Work in worker processes: results in order, errors and progress brought back, workers ended."""

import math
import os
import time

import pytest

from scalf_opt.workers import WorkerDiedError, map_in_processes, worker_progress


def test_results_come_back_in_the_order_of_the_items():
    assert map_in_processes(math.sqrt, [9.0, 1.0, 4.0], 2) == [3.0, 1.0, 2.0]


def test_one_worker_is_a_plain_loop_whose_progress_reaches_the_caller():
    labels: list[str] = []
    assert map_in_processes(worker_progress, ["a", "b"], 1, labels.append) == [None, None]
    assert labels == ["a", "b"]
    worker_progress("dropped")  # outside the call: nowhere to go, and no error
    assert labels == ["a", "b"]


def test_progress_labels_of_the_workers_reach_the_caller():
    labels: list[str] = []
    assert map_in_processes(worker_progress, ["RF", "LH"], 2, labels.append) == [None, None]
    assert sorted(labels) == ["LH", "RF"]


def test_an_error_in_a_worker_is_raised_here_and_ends_the_others():
    start = time.monotonic()
    with pytest.raises(ValueError, match="math domain error"):
        map_in_processes(math.sqrt, [-1.0, 4.0], 2)
    with pytest.raises(ValueError, match="non-negative"):
        # the sleeping worker is killed, not waited for (it would sleep ten minutes)
        map_in_processes(time.sleep, [600.0, -1.0], 2)
    assert time.monotonic() - start < 600.0


def test_a_worker_that_dies_is_an_error_that_says_so():
    with pytest.raises(WorkerDiedError, match="exit code 3"):
        map_in_processes(os._exit, [3, 3], 2)


def test_labels_of_a_pool_of_spawned_workers_reach_this_process_sink():
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    from scalf_opt.workers import progress_to, relayed_labels

    labels: list[str] = []
    context = multiprocessing.get_context("spawn")
    with (
        progress_to(labels.append),
        relayed_labels(context) as (initializer, initargs),
        ProcessPoolExecutor(2, context, initializer, initargs) as pool,
    ):
        assert list(pool.map(worker_progress, ["0.5 m/s", "1 m/s"])) == [None, None]
    assert sorted(labels) == ["0.5 m/s", "1 m/s"]
