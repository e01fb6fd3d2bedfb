"""``python -m scalf_opt`` and the ``scalf-opt`` console script: the command line.

Ctrl-C ends a command with exit code 130 and one line, never a traceback, from the program's
first instant: :func:`run` installs a handler that exits with 130 before it imports the command
line (an interruption while Python imports it printed a ``KeyboardInterrupt`` traceback), and
that handler is back in place once the command line's own (:func:`~scalf_opt.interrupts
.stop_on_signals`) are removed as the command returns.
"""

from __future__ import annotations

import signal
import sys
from types import FrameType
from typing import NoReturn


def _interrupted(signum: int, frame: FrameType | None) -> NoReturn:
    raise SystemExit(130)


def run() -> NoReturn:
    """Run the command line of ``sys.argv`` and exit with its code."""
    signal.signal(signal.SIGINT, _interrupted)
    from scalf_opt.cli.app import main

    sys.exit(main())


if __name__ == "__main__":
    run()
