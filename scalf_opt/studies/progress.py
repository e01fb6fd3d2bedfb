"""A study's progress: a one-line bar on a terminal, heartbeat lines on stderr otherwise.

The bar is drawn on a terminal only (never into a log or a pipe); elsewhere a
:class:`~scalf_opt.heartbeat.Heartbeat` says every 10 s how many cases are done. Both end with
what a running case last said it is doing (:meth:`Progress.note`: the cheapest-gait search
names each gait it tries), so a case of many minutes is not a silent one.
"""

from __future__ import annotations

import shutil
import sys
import threading
import time
from typing import TextIO

from scalf_opt.heartbeat import Heartbeat


class Progress:
    """Counts finished cases and redraws ``[#####.....] 5/10 cases, 1 failed, 12 s``.

    Args:
        total: Number of cases to run.
        stream: Where to draw (default stderr).
        enabled: Draw at all; ``None``: only when ``stream`` is a terminal.
        label: The command's name in the heartbeat lines.
    """

    WIDTH = 30

    def __init__(
        self,
        total: int,
        stream: TextIO | None = None,
        enabled: bool | None = None,
        label: str = "study",
    ):
        self.total = total
        self.stream = stream or sys.stderr
        self.enabled = self.stream.isatty() if enabled is None else enabled
        self.done = 0
        self.failed = 0
        self.start = time.monotonic()
        self.last_note = ""
        self._drawn = 0  # characters of the line on the terminal
        self._lock = threading.Lock()  # notes come from a relay thread
        self._heartbeat: Heartbeat | None = None
        if enabled is None and not self.enabled and total:
            self._heartbeat = Heartbeat(label).__enter__()
            self._heartbeat.doing = f"0/{total} cases done"

    def update(self, ok: bool) -> None:
        """One more case finished (``ok`` or not)."""
        with self._lock:
            self.done += 1
            self.failed += 0 if ok else 1
            self._show()

    def note(self, label: str) -> None:
        """What a running case is doing now (shown until the next note)."""
        with self._lock:
            self.last_note = label
            self._show()

    def _show(self) -> None:
        failed = f", {self.failed} not ok" if self.failed else ""
        note = f"; {self.last_note}" if self.last_note and self.done < self.total else ""
        if self._heartbeat is not None:
            self._heartbeat.doing = f"{self.done}/{self.total} cases done{failed}{note}"
        if not self.enabled or self.total == 0:
            return
        filled = round(self.WIDTH * self.done / self.total)
        bar = "#" * filled + "." * (self.WIDTH - filled)
        elapsed = time.monotonic() - self.start
        line = f"[{bar}] {self.done}/{self.total} cases{failed}, {elapsed:.0f} s{note}"
        line = line[: shutil.get_terminal_size().columns - 1]  # one line, or \r cannot redraw it
        self.stream.write("\r" + line.ljust(self._drawn))  # over a longer previous line
        self._drawn = len(line)
        self.stream.flush()

    def close(self) -> None:
        """End the line the bar was drawn on (or stop the heartbeat)."""
        if self._heartbeat is not None:
            self._heartbeat.__exit__(None, None, None)
            self._heartbeat = None
        if self.enabled and self.total:
            self.stream.write("\n")
            self.stream.flush()
