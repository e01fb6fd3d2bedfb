"""Ctrl-C and SIGTERM stop the program, even where a library swallows the exception.

Python turns a signal into an exception raised wherever the program happens to be. Two kinds of
place swallow it: CasADi's Ipopt interface, which checks for signals between iterations, catches
the exception and ends the solve as if it had failed ("NonIpopt_Exception_Thrown"); and library
code with a bare ``except:`` (an import that happens to be running). The program would then go
on with the next solve, or the next case of a study.

So the command line's handlers (:func:`stop_on_signals`) also remember the signal, and the
long-running loops call :func:`raise_if_stopped` between steps; :func:`interruptible` wraps a
native solve, and raises the swallowed signal's exception once the solve has returned. From the
Python API (no handlers installed), Ctrl-C during an Ipopt solve is raised the same way.

Signals reach only the main thread. Solves running in worker threads (:func:`map_in_threads`)
are stopped by their iteration callback, which asks :func:`stop_requested` (a signal the
handlers received, or the main thread unwinding from an exception) and ends the solve.
"""

from __future__ import annotations

import contextlib
import signal
import sys
import threading
from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import FIRST_EXCEPTION, Future, ThreadPoolExecutor, wait
from types import FrameType
from typing import TypeVar

from scalf_opt.files import captured_native_output

T = TypeVar("T")
R = TypeVar("R")

_received: list[int] = []
"""Signals the command line's handlers received (cleared when the command ends)."""


class Interrupted(KeyboardInterrupt):
    """Ctrl-C as the command line raises it: caught wherever ``KeyboardInterrupt`` is.

    Why a subclass: CPython takes a ``KeyboardInterrupt`` of exactly that type that leaves code
    run from source text (``exec`` or ``eval`` of a string, which dataclasses, named tuples and
    enums do as their modules are imported) for an unhandled ^C, and under ``python -m`` the
    interpreter then ends itself by SIGINT at exit, although the command caught the exception and
    exited with 130 (seen as -2 by a parent process; about once in a hundred Ctrl-C's during a
    command's first imports). A subclass is not that exact type.
    """


def _raise_for(signum: int) -> None:
    if signum == signal.SIGTERM:
        raise SystemExit(128 + signum)
    raise Interrupted


def stop_code() -> int | None:
    """The exit code of the signal the command line's handlers received (130, 143), if any."""
    if not _received:
        return None
    return 128 + (signal.SIGINT if _received[0] == signal.SIGINT else _received[0])


_cancelled = threading.Event()
"""Set while :func:`map_in_threads` unwinds: its workers stop at their next step."""


def stop_requested() -> bool:
    """A signal was received or the running workers are being cancelled.

    Thread-safe and cheap: what a native solver's iteration callback asks (in any thread).
    """
    return bool(_received) or _cancelled.is_set()


def raise_if_stopped() -> None:
    """Raise again a signal that a library swallowed (``KeyboardInterrupt`` or ``SystemExit``).

    In a worker of :func:`map_in_threads` being cancelled, ``KeyboardInterrupt``.
    """
    if _received:
        _raise_for(_received[0])
    if _cancelled.is_set() and threading.current_thread() is not threading.main_thread():
        raise Interrupted


def results_in_order(futures: list[Future[R]]) -> list[R]:
    """The futures' results in order, once all are done.

    As soon as one fails: the error of the first in order that failed (not the first to fail).
    """
    wait(futures, return_when=FIRST_EXCEPTION)
    for future in futures:
        if future.done() and future.exception() is not None:
            return [future.result()]  # raises it
    return [future.result() for future in futures]


def map_in_threads(fn: Callable[[T], R], items: Sequence[T], workers: int) -> list[R]:
    """``[fn(item) for item in items]``, on up to ``workers`` threads, results in order.

    For native solvers that release the GIL (CasADi's). The first exception is raised once
    every worker has stopped; so is a signal (Ctrl-C, SIGTERM) received meanwhile by the main
    thread: the workers' solvers then end at their next iteration (:func:`stop_requested`)
    instead of running to the end. One worker, or one item: a plain loop in this thread.
    """
    if workers <= 1 or len(items) <= 1:
        return [fn(item) for item in items]
    pool = ThreadPoolExecutor(max_workers=min(workers, len(items)))
    try:
        return results_in_order([pool.submit(fn, item) for item in items])
    except BaseException:
        _cancelled.set()
        raise
    finally:
        pool.shutdown(wait=True, cancel_futures=True)
        _cancelled.clear()


@contextlib.contextmanager
def stop_on_signals() -> Iterator[None]:
    """Install the command line's handlers, which remember the signal they raise.

    Ctrl-C raises :class:`Interrupted` (a ``KeyboardInterrupt``) and SIGTERM (``kill``, a job
    scheduler) ``SystemExit(143)``, so that both unwind and remove the temporary files.
    """

    def stop(signum: int, frame: FrameType | None) -> None:
        _received.append(signum)
        _raise_for(signum)

    if threading.current_thread() is not threading.main_thread():
        yield  # the command run from a thread: Python delivers signals to the main thread only
        return

    def unraisable(info: sys.UnraisableHookArgs) -> None:
        if not _received:  # the signal's exception, raised in a finaliser or a callback: quiet
            previous_hook(info)

    previous_hook = sys.unraisablehook
    sys.unraisablehook = unraisable
    try:
        with _handling(stop):
            yield
    finally:
        sys.unraisablehook = previous_hook
        _received.clear()


@contextlib.contextmanager
def _handling(handler: Callable[[int, FrameType | None], None]) -> Iterator[None]:
    """``handler`` for SIGINT and SIGTERM inside the block; the handlers before restored after."""
    previous = {s: signal.signal(s, handler) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield
    finally:
        for signum, before in previous.items():
            signal.signal(signum, before)


@contextlib.contextmanager
def signals_held() -> Iterator[None]:
    """Hold Ctrl-C and SIGTERM back while the block runs; deliver them once it is done.

    For imports of native code that calls Python while it initialises: trimesh (which yourdfpy
    imports) loads manifold3d (its ``easy`` extra, which yourdfpy requires), a nanobind extension
    that builds Python enums as it loads, and an exception raised there by a signal's handler
    aborted the interpreter or crashed it (SIGABRT, SIGSEGV: 7 of 120 studies of a variant
    stopped by Ctrl-C within a tenth of a second of their first scratch file, on a busy
    machine). Inside the block a signal is only noted; afterwards the handlers in place before
    are restored and the first signal noted is raised again, so it takes effect as it would
    have (the command line's handlers raise, the defaults end the program). In a thread other
    than the main one (signals reach the main thread only): the block runs as it is.
    """
    if threading.current_thread() is not threading.main_thread():
        yield
        return
    held: list[int] = []

    def hold(signum: int, frame: FrameType | None) -> None:
        held.append(signum)

    try:
        with _handling(hold):
            yield
    finally:
        if held:
            signal.raise_signal(held[0])


@contextlib.contextmanager
def interruptible() -> Iterator[None]:
    """Run a native solver inside: a signal it swallowed is raised again when it returns.

    What the solver's library prints on stderr is held back until it returns, and dropped when
    a signal stopped it (CasADi's ``KeyboardInterruptException`` warning, with its source path):
    the command then ends with its one line.
    """
    if threading.current_thread() is not threading.main_thread():
        yield  # signals reach the main thread; the solver stops on stop_requested()
        raise_if_stopped()
        return
    previous = signal.getsignal(signal.SIGINT)
    received: list[int] = []

    def note(signum: int, frame: FrameType | None) -> None:
        received.append(signum)
        if callable(previous):
            previous(signum, frame)  # raises: in Python it propagates, in CasADi it ends the solve
        raise Interrupted

    if callable(previous):
        signal.signal(signal.SIGINT, note)
    try:
        with captured_native_output(fds=(2,)) as printed:
            yield
    finally:
        if callable(previous):
            signal.signal(signal.SIGINT, previous)
    if printed and not (received or _received):  # no signal: what it printed, now
        with contextlib.suppress(OSError, ValueError):
            sys.stderr.write("\n".join(printed) + "\n")
            sys.stderr.flush()
    if received:  # Ctrl-C, swallowed by the solver
        raise Interrupted
    raise_if_stopped()
