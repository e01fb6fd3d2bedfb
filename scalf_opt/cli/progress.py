"""Progress on long work: a bar on a terminal, a heartbeat line on stderr everywhere else.

On a terminal (and not under CI) a tqdm bar on stderr shows the current step. When the output
is a pipe or a log, a line ``scalf-opt: <what>: <step> (<elapsed> s)`` goes to stderr at least
every :data:`HEARTBEAT_S` seconds while the work lasts, so a long solve is never silent; work
that ends sooner prints nothing. ``--quiet`` turns both off.
"""

from __future__ import annotations

import sys
import threading
import time
from types import TracebackType

from scalf_opt.cli.console import progress_enabled

HEARTBEAT_S = 10.0
"""The longest silence on stderr during long work when the output is not a terminal [s]."""


class ProgressBar:
    """A context manager with ``step(label)``: a bar on a terminal, heartbeat lines otherwise.

    Args:
        total: Number of steps (``None`` when not known beforehand: a count).
        what: What is being done (the bar's prefix, the heartbeat's subject).
        enabled: False to print nothing at all (``--quiet``).
        heartbeat_s: Seconds between heartbeat lines when there is no terminal.
    """

    def __init__(
        self,
        total: int | None,
        what: str,
        enabled: bool = True,
        heartbeat_s: float = HEARTBEAT_S,
    ) -> None:
        self._bar = None
        self._what = what
        self._label = "starting"
        self._start = time.monotonic()
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        if enabled and progress_enabled():
            from tqdm import tqdm

            self._bar = tqdm(total=total, desc=what, unit="step", leave=False, dynamic_ncols=True)
        elif enabled:
            self._thread = threading.Thread(
                target=self._beat, args=(heartbeat_s,), name="scalf-opt-heartbeat", daemon=True
            )
        self._started = False

    def _beat(self, every_s: float) -> None:
        while not self._stop.wait(every_s):
            elapsed = time.monotonic() - self._start
            try:
                sys.stderr.write(f"scalf-opt: {self._what}: {self._label} ({elapsed:.0f} s)\n")
                sys.stderr.flush()
            except (OSError, ValueError):  # stderr closed: nobody is listening
                return

    def step(self, label: str) -> None:
        """Start the next step, ``label`` describing it (the previous one is done)."""
        self._label = label
        if self._bar is None:
            return
        if self._started:
            self._bar.update(1)
        self._started = True
        self._bar.set_postfix_str(label, refresh=True)

    def __enter__(self) -> ProgressBar:
        if self._thread is not None:
            self._thread.start()
        return self

    def __exit__(
        self,
        kind: type[BaseException] | None,
        value: BaseException | None,
        traceback: TracebackType | None,
    ) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join()
        if self._bar is not None:
            if kind is None and self._started:
                self._bar.update(1)
            self._bar.close()
