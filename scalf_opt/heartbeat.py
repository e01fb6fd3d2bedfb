"""A heartbeat on stderr: long work that nobody watches on a terminal is never silent.

While a :class:`Heartbeat` is running, a line ``scalf-opt: <what>: <doing> (<elapsed> s)`` is
written to stderr every :data:`HEARTBEAT_S` seconds; work that ends sooner prints nothing. The
command line uses it when its output is a pipe or a log (on a terminal a progress bar shows the
same), for solves and studies alike.
"""

from __future__ import annotations

import contextlib
import sys
import threading
import time
from collections.abc import Callable, Iterator
from types import TracebackType

HEARTBEAT_S = 10.0
"""The longest silence on stderr during long work when the output is not a terminal [s]."""

_listeners: list[Callable[[str | None], None]] = []
"""Who shows what :func:`meanwhile` announces (the command line's progress, while it runs)."""


@contextlib.contextmanager
def meanwhile(doing: str) -> Iterator[None]:
    """Long work inside a step that the step's label does not say (compiling a new kernel).

    Shown beside the current step while the block runs (``joint-6 at 425 Hz: compiling ...``),
    by whatever listens (:func:`listening`); nothing when nobody does.
    """
    for listener in list(_listeners):
        listener(doing)
    try:
        yield
    finally:
        for listener in list(_listeners):
            listener(None)


@contextlib.contextmanager
def listening(listener: Callable[[str | None], None]) -> Iterator[None]:
    """Inside the block ``listener`` gets what :func:`meanwhile` announces, then ``None``."""
    _listeners.append(listener)
    try:
        yield
    finally:
        _listeners.remove(listener)


class Heartbeat:
    """A context manager that reports what is being done at a fixed interval.

    Args:
        what: The subject of every line (the command).
        every_s: Seconds between lines.
    """

    def __init__(self, what: str, every_s: float = HEARTBEAT_S) -> None:
        self.what = what
        self.doing = "starting"
        self._every_s = every_s
        self._start = time.monotonic()
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._beat, name="scalf-opt-heartbeat", daemon=True)

    def _beat(self) -> None:
        while not self._stop.wait(self._every_s):
            elapsed = time.monotonic() - self._start
            try:
                sys.stderr.write(f"scalf-opt: {self.what}: {self.doing} ({elapsed:.0f} s)\n")
                sys.stderr.flush()
            except (OSError, ValueError):  # stderr closed: nobody is listening
                return

    def __enter__(self) -> Heartbeat:
        self._thread.start()
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        value: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        self._stop.set()
        self._thread.join()
