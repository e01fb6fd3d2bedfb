"""Where a command's output goes: text or JSON on stdout, notes and errors on stderr.

Writing survives a closed pipe (``scalf-opt paper | head``): the first ``BrokenPipeError`` points
stdout at the null device and later output is dropped, so the command still finishes its work and
writes its files, and Python does not complain at exit.
"""

from __future__ import annotations

import os
import re
import sys
from typing import Any, TextIO

_UNSAFE = re.compile("[\x00-\x08\x0b-\x1f\x7f-\x9f\u200e\u200f\u202a-\u202e\u2066-\u2069]")
"""Characters a terminal acts on instead of showing: C0 and C1 controls (escape sequences,
carriage return, bell) but the newline and the tab, and the bidirectional overrides."""


def terminal_safe(text: str) -> str:
    r"""``text`` with every character a terminal would act on shown as its escape (``\x1b``).

    File names, URDF names and log headers come from untrusted files; printed raw, an escape
    sequence in one could move the cursor, retitle the window or hide the rest of the line.
    """
    return _UNSAFE.sub(lambda m: m.group().encode("unicode_escape").decode("ascii"), text)


MAX_ERROR_CHARS = 1000
"""The longest error line printed: the start says what is wrong and where; a value or a list
that an input makes megabytes long is cut in the middle, not echoed whole."""


def shortened(text: str, limit: int) -> str:
    """``text``, or its start and end around ``" ... (N characters left out) ... "``."""
    if len(text) <= limit:
        return text
    keep = limit - 60
    head, tail = text[: keep * 3 // 4], text[-(keep // 4) :]
    return f"{head} ... ({len(text) - len(head) - len(tail)} characters left out) ... {tail}"


class Console:
    """The command's output channels.

    Args:
        quiet: Drop the human-readable text (files are still written, errors still shown).
        json_output: Print the results as JSON on stdout instead of text.
    """

    def __init__(self, quiet: bool = False, json_output: bool = False) -> None:
        self.quiet = quiet
        self.json_output = json_output
        self._closed = False

    def _write(self, stream: TextIO, text: str) -> None:
        if self._closed and stream is sys.stdout:
            return
        try:
            stream.write(terminal_safe(text) + "\n")
            stream.flush()
        except BrokenPipeError:
            self._closed = True
            devnull = os.open(os.devnull, os.O_WRONLY)
            os.dup2(devnull, sys.stdout.fileno())
            os.close(devnull)

    def text(self, text: str) -> None:
        """Human-readable output on stdout (not with ``--quiet`` or ``--json``)."""
        if not (self.quiet or self.json_output):
            self._write(sys.stdout, text)

    def json(self, data: Any) -> None:
        """Machine-readable output on stdout (only with ``--json``), without run times."""
        if self.json_output:
            from scalf_opt.io.results import split_timings, to_json

            self._write(sys.stdout, to_json(split_timings(data)[0]).rstrip("\n"))

    def note(self, text: str) -> None:
        """A remark for the user on stderr (not with ``--quiet``)."""
        if not self.quiet:
            self._write(sys.stderr, f"scalf-opt: {text}")

    def error(self, text: str) -> None:
        """One line on stderr, always, of at most :data:`MAX_ERROR_CHARS` characters."""
        line = " ".join(part for part in text.splitlines() if part.strip())
        self._write(sys.stderr, "scalf-opt: error: " + shortened(line, MAX_ERROR_CHARS))


def progress_enabled() -> bool:
    """A progress bar is drawn only when stdout is a terminal and not under CI."""
    return sys.stdout.isatty() and not os.environ.get("CI")
