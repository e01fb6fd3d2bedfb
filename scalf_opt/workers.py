"""Independent solves in worker processes: :func:`map_in_processes`.

Ipopt's interface to MUMPS holds one lock for the whole process, so two large solves on two
threads factorize one after the other (measured on SCalf's two free-trajectory bounds:
docs/speed-log.md). Solves whose time is the linear solver therefore run in worker
processes, each a fresh interpreter (``python -m scalf_opt.workers``) that reads one pickled
``(function, item)`` on its standard input and writes pickled frames back: progress labels, then
the result or the error.

A fresh interpreter, not :mod:`multiprocessing`: its ``spawn`` re-runs the caller's main script
in every worker, so a script without an ``if __name__ == "__main__":`` guard would start the
work again in each worker, and ``fork`` copies this process's CasADi and Pinocchio state and
any lock another thread holds. The worker imports the package first (its import-time settings,
:mod:`scalf_opt.blas_kernels`, hold there too), so the answers are bitwise those of a loop.

:func:`imap_in_processes` keeps its workers for many items (a study's cases: a fresh interpreter
costs about two seconds of imports and model loading, more than a small case) and yields each
result as it comes, an item's error in place of its result.

The workers ignore Ctrl-C (the terminal sends it to them too); the main process, stopped by a
signal or an error, kills them.
"""

from __future__ import annotations

import contextlib
import os
import pickle
import queue
import signal
import subprocess
import sys
import threading
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Future, ThreadPoolExecutor
from typing import IO, Any, TypeVar

from scalf_opt.errors import ScalfError
from scalf_opt.files import remove_stale_scratch
from scalf_opt.interrupts import results_in_order

T = TypeVar("T")
R = TypeVar("R")

_channel: IO[bytes] | None = None
"""In a worker: the pipe its frames go to (its original standard output)."""

_progress: Callable[[str], None] | None = None
"""Where :func:`worker_progress` sends a label in this process (the plain loop's ``progress``)."""


class WorkerDiedError(RuntimeError):
    """A worker process ended without an answer (killed, or out of memory).

    Not the input's fault, so not a :class:`~scalf_opt.errors.ScalfError`: the command exits 1.
    """


def worker_progress(label: str) -> None:
    """The progress callback of work run by :func:`map_in_processes`.

    The label reaches that call's ``progress``, in the main process.
    """
    if _channel is not None:
        _send("progress", label)
    elif _progress is not None:
        _progress(label)


def in_worker_process() -> bool:
    """This process is a worker of this module (its work should not start workers of its own)."""
    return _channel is not None


@contextlib.contextmanager
def progress_to(callback: Callable[[str], None]) -> Iterator[None]:
    """Inside the block, :func:`worker_progress` in this process calls ``callback``."""
    global _progress
    previous, _progress = _progress, callback
    try:
        yield
    finally:
        _progress = previous


def map_in_processes(
    fn: Callable[[T], R],
    items: Sequence[T],
    workers: int,
    progress: Callable[[str], None] | None = None,
) -> list[R]:
    """``[fn(item) for item in items]``, on up to ``workers`` worker processes, results in order.

    ``fn`` is a module-level function; the items, results and errors pickle. Labels the work
    passes to :func:`worker_progress` go to ``progress`` (called from a thread of this
    process). The first error in item order is raised once the other workers are killed; so is
    Ctrl-C or SIGTERM received here. One worker, or one item: a plain loop in this process.
    """
    if workers <= 1 or len(items) <= 1:
        with progress_to(progress) if progress is not None else contextlib.nullcontext():
            return [fn(item) for item in items]
    with WorkerProcesses(min(workers, len(items)), progress) as processes:
        return results_in_order([processes.submit(fn, item) for item in items])


BACKGROUND_NICE = 10
"""How much lower a background job's scheduling priority is (``nice``): at 10 the kernel gives
a job of the default priority about nine tenths of a core it shares with one."""


class WorkerProcesses:
    """Work submitted to worker processes, each item a fresh interpreter, collected later.

    At most ``concurrent`` workers run at once (items beyond wait for one to end); each may use
    ``cores // concurrent`` threads (this process's :func:`thread_budget`, shared), so that the
    workers do not crowd the cores they share. An item submitted with ``background=True`` runs
    at a lower scheduling priority (:data:`BACKGROUND_NICE`): where the items outnumber the
    cores, the others, the critical path, get a core first and the background ones fill what is
    left (``paper`` starts its whole-body line and its free stance before Tables 5 and 6, whose
    optima the bounds need, and the bounds take the lead once they start).

    Leaving the block (by an error, Ctrl-C or SIGTERM too) kills the workers still running:
    work whose result was not asked for is dropped.
    """

    def __init__(self, concurrent: int, progress: Callable[[str], None] | None = None) -> None:
        concurrent = max(1, concurrent)
        self._progress = progress
        self._threads = _threads_each(concurrent)
        self._pool = ThreadPoolExecutor(max_workers=concurrent)
        self._lock = threading.Lock()
        self._stopping = threading.Event()
        self._running: list[subprocess.Popen[bytes]] = []

    def __enter__(self) -> WorkerProcesses:
        return self

    def __exit__(self, *exc: object) -> None:
        with self._lock:
            self._stopping.set()
            for worker in self._running:
                if worker.poll() is None:
                    worker.kill()
        self._pool.shutdown(wait=True, cancel_futures=True)
        _end(self._running)

    def submit(self, fn: Callable[[T], R], item: T, background: bool = False) -> Future[R]:
        """``fn(item)`` in a worker process, started as soon as fewer than ``concurrent`` run."""
        nice = BACKGROUND_NICE if background else 0
        return self._pool.submit(self._run, fn, item, nice)

    def _run(self, fn: Callable[[T], R], item: T, nice: int) -> R:
        with self._lock:
            if self._stopping.is_set():
                raise WorkerDiedError("stopped before it started")
            worker = _start_worker(self._threads, nice)
            self._running.append(worker)
        return _exchange(worker, fn, item, self._progress)


def imap_in_processes(
    fn: Callable[[T], R], items: Sequence[T], workers: int
) -> Iterator[tuple[int, R | Exception]]:
    """``(index, fn(items[index]))`` as each finishes, on up to ``workers`` worker processes.

    Each worker takes item after item. An item whose ``fn`` raises yields the error in place of
    its result and the others go on; a worker that dies yields :class:`WorkerDiedError` for its
    item, and a fresh worker takes the next. Labels the work passes to :func:`worker_progress`
    reach :func:`worker_progress` in this process (from a thread). Closing the iterator, an
    error in the caller, Ctrl-C or SIGTERM kill the workers.
    """
    pending = iter(enumerate(items))
    threads = _threads_each(min(workers, len(items)))
    lock = threading.Lock()
    stopping = threading.Event()
    running: list[subprocess.Popen[bytes]] = []
    done: queue.SimpleQueue[tuple[int, R | Exception] | None] = queue.SimpleQueue()

    def drive() -> None:
        worker: subprocess.Popen[bytes] | None = None
        try:
            while True:
                with lock:
                    following = None if stopping.is_set() else next(pending, None)
                    if following is None:
                        return
                    if worker is None:
                        worker = _start_worker(threads)
                        running.append(worker)
                index, item = following
                outcome: R | Exception
                try:
                    outcome = _exchange(worker, fn, item, None, last=False)
                except WorkerDiedError as exc:
                    outcome, worker = exc, None
                except Exception as exc:  # fn's error: the worker serves the next item
                    outcome = exc
                done.put((index, outcome))
        finally:
            if worker is not None and worker.stdin is not None:
                with contextlib.suppress(OSError):
                    worker.stdin.close()  # it ends once it reads the end of its input
            done.put(None)

    drivers = [threading.Thread(target=drive, daemon=True) for _ in range(min(workers, len(items)))]
    for thread in drivers:
        thread.start()
    finished = False
    try:
        active = len(drivers)
        while active:
            got = done.get()
            if got is None:
                active -= 1
            else:
                yield got
        finished = True
    finally:
        with lock:
            stopping.set()
            for worker in running:
                if not finished and worker.poll() is None:
                    worker.kill()
        for thread in drivers:
            thread.join()
        _end(running)


def _end(workers: list[subprocess.Popen[bytes]]) -> None:
    """Wait for ``workers`` to end, then remove the scratch folders a killed one left."""
    for worker in workers:
        worker.wait()
    remove_stale_scratch(pids=[worker.pid for worker in workers])


THREADS_VARIABLE = "SCALF_OPT_THREADS"
"""The environment variable that caps the threads a process's solves use (set in workers)."""


def thread_budget() -> int:
    """Threads this process's solves may use at once: :data:`THREADS_VARIABLE`, else the cores."""
    with contextlib.suppress(KeyError, ValueError):
        return max(1, int(os.environ[THREADS_VARIABLE]))
    return os.cpu_count() or 1


def _threads_each(workers: int) -> int:
    """Threads each of ``workers`` workers may use: this process's budget shared, at least one."""
    return max(1, thread_budget() // max(1, workers))


def _start_worker(threads: int, nice: int = 0) -> subprocess.Popen[bytes]:
    """A fresh interpreter serving work on its standard input (:func:`_serve`).

    Its solves use at most ``threads`` threads; ``nice``: how much lower its priority is.
    """
    return subprocess.Popen(
        [sys.executable, "-m", "scalf_opt.workers", str(nice)],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        env={**os.environ, THREADS_VARIABLE: str(threads)},
    )


def _exchange(
    worker: subprocess.Popen[bytes],
    fn: Callable[[T], R],
    item: T,
    progress: Callable[[str], None] | None,
    last: bool = True,
) -> R:
    """Send the work to ``worker``, relay its progress, return its result or raise its error.

    ``last``: the worker gets no more work (its input is closed, and it is waited for).
    """
    assert worker.stdin is not None and worker.stdout is not None
    frame = pickle.dumps((fn, item))  # work that does not pickle fails here, before a byte is sent
    try:
        worker.stdin.write(frame)
        if last:
            worker.stdin.close()
        else:
            worker.stdin.flush()
    except BrokenPipeError:
        pass  # it died at once: said below
    while True:
        try:
            kind, payload = pickle.load(worker.stdout)
        except (EOFError, pickle.UnpicklingError) as exc:
            code = worker.wait()
            raise WorkerDiedError(
                f"a worker process ended without an answer (exit code {code})"
            ) from exc
        if kind == "progress":
            (progress or worker_progress)(payload)  # none given: to this process's own sink
            continue
        if last:
            worker.wait()
        if kind == "result":
            return payload
        raise payload


def _send(kind: str, payload: Any) -> None:
    assert _channel is not None
    pickle.dump((kind, payload), _channel)
    _channel.flush()


def _serve(nice: int = 0) -> int:
    """A worker's life: read work, do it, write the answer; until its input ends.

    ``nice``: how much to lower its scheduling priority first.
    """
    global _channel
    if nice:
        os.nice(nice)
    signal.signal(signal.SIGINT, signal.SIG_IGN)  # the main process ends the workers
    # frames go to the original standard output; anything else printed goes to stderr
    _channel = os.fdopen(os.dup(1), "wb")
    os.dup2(2, 1)
    sys.stdout = sys.stderr
    while True:
        try:
            fn, item = pickle.load(sys.stdin.buffer)
        except EOFError:  # no more work
            return 0
        try:
            result = fn(item)
        except Exception as exc:  # the main process raises it
            try:
                _send("error", exc)
            except (pickle.PicklingError, TypeError, AttributeError):  # it does not pickle
                kind = ScalfError if isinstance(exc, ScalfError) else RuntimeError
                _send("error", kind(f"{type(exc).__name__}: {exc}"))
            continue
        _send("result", result)


if __name__ == "__main__":
    # run as a script this file is ``__main__``: serve from the package's module, the one whose
    # worker_progress the work was pickled with
    from scalf_opt.workers import _serve as serve

    sys.exit(serve(int(sys.argv[1]) if len(sys.argv) > 1 else 0))
