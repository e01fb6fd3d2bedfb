"""Work in worker processes: results in order, errors and progress brought back, workers ended."""

import math
import os
import pickle
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


def test_imap_yields_every_result_with_its_index_and_an_error_in_place_of_its_result():
    from scalf_opt.workers import imap_in_processes, progress_to

    labels: list[str] = []
    with progress_to(labels.append):
        got = dict(imap_in_processes(worker_progress, ["0.5 m/s", "1 m/s", "1.5 m/s"], 2))
    assert got == {0: None, 1: None, 2: None}
    assert sorted(labels) == ["0.5 m/s", "1 m/s", "1.5 m/s"]
    got = dict(imap_in_processes(math.sqrt, [9.0, -1.0, 4.0, 16.0], 2))
    assert (got[0], got[2], got[3]) == (3.0, 2.0, 4.0)
    assert isinstance(got[1], ValueError) and "math domain error" in str(got[1])
    # an item that does not pickle is its own error; the worker serves the next ones
    got = dict(imap_in_processes(_length, ["ab", lambda: None, "abcd"], 1))
    assert (got[0], got[2]) == (2, 4) and isinstance(got[1], pickle.PicklingError | AttributeError)


def test_imap_workers_serve_many_items_and_a_dead_one_is_replaced():
    from scalf_opt.workers import imap_in_processes

    pids = dict(imap_in_processes(_pid_after, [0.0] * 6, 2))
    assert len(set(pids.values())) == 2  # two workers, three items each (not one per item)
    got = dict(imap_in_processes(_exit_on_three, [1, 3, 2, 4], 1))
    assert (got[0], got[2], got[3]) == (1, 2, 4)  # a fresh worker took the items after
    assert isinstance(got[1], WorkerDiedError) and "exit code 3" in str(got[1])


def test_closing_imap_early_kills_its_workers():
    from scalf_opt.workers import imap_in_processes

    results = imap_in_processes(time.sleep, [0.0, 600.0, 600.0], 2)
    start = time.perf_counter()
    assert next(results) == (0, None)
    results.close()
    assert time.perf_counter() - start < 60.0  # not the 600 s sleeps: the workers were killed


def _pid_after(seconds: float) -> int:
    time.sleep(seconds + 0.2)  # long enough that both workers take items
    return os.getpid()


def _length(text: str) -> int:
    return len(text)


def _exit_on_three(value: int) -> int:
    if value == 3:
        os._exit(3)
    return value


def test_workers_share_the_cores_and_background_work_yields_to_the_rest(monkeypatch):
    from scalf_opt.workers import (
        BACKGROUND_NICE,
        THREADS_VARIABLE,
        WorkerProcesses,
        imap_in_processes,
        thread_budget,
    )

    monkeypatch.delenv(THREADS_VARIABLE, raising=False)  # this process: its cores to share
    cores = os.cpu_count() or 1
    # each of n workers may use cores // n threads (at least one), what the legs' threads read
    assert map_in_processes(os.getenv, [THREADS_VARIABLE] * 2, 2) == [str(max(1, cores // 2))] * 2
    assert dict(imap_in_processes(os.getenv, [THREADS_VARIABLE], 4)) == {0: str(cores)}
    assert thread_budget() == cores
    monkeypatch.setenv(THREADS_VARIABLE, "4")  # a worker with four threads shares those four
    assert map_in_processes(os.getenv, [THREADS_VARIABLE] * 2, 2) == ["2", "2"]
    monkeypatch.delenv(THREADS_VARIABLE)
    here = os.nice(0)
    with WorkerProcesses(3) as processes:
        low = processes.submit(os.nice, 0, background=True)
        normal = processes.submit(os.nice, 0)
        assert (low.result(), normal.result()) == (min(19, here + BACKGROUND_NICE), here)


def test_leaving_the_block_kills_work_whose_result_was_not_asked_for():
    from scalf_opt.workers import WorkerProcesses

    start = time.perf_counter()
    with WorkerProcesses(2) as processes:
        sleeping = processes.submit(time.sleep, 600.0, background=True)
        assert processes.submit(math.sqrt, 4.0).result() == 2.0
    assert time.perf_counter() - start < 60.0  # not the 600 s sleep: its worker was killed
    with pytest.raises(WorkerDiedError):
        sleeping.result()
