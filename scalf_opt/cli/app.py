"""Parse the command line, dispatch to a command, and turn errors into one line and an exit code.

Exit codes: 0 success; 2 bad input (:class:`~scalf_opt.errors.ScalfError`: one line on stderr,
no traceback); 3 an optimizer did not converge (the command says which); 130 interrupted; 141
the reader of the output went away (a pipe into ``head``).
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence

from scalf_opt import __version__
from scalf_opt.cli.commands import COMMANDS
from scalf_opt.errors import ScalfError


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every command."""
    parser = argparse.ArgumentParser(
        prog="scalf-opt",
        description="Energy-efficient swing-foot trajectories for legged robots (SCalf paper).",
    )
    parser.add_argument("--version", action="version", version=f"scalf-opt {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for command in COMMANDS:
        p = sub.add_parser(command.NAME, help=command.HELP, description=command.HELP)
        command.add_arguments(p)
        p.set_defaults(run=command.run)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``scalf-opt`` console script."""
    args = build_parser().parse_args(argv)
    try:
        code = int(args.run(args))
        sys.stdout.flush()  # inside the try: a closed pipe surfaces here, not at exit
        return code
    except ScalfError as exc:
        print(f"scalf-opt: error: {exc}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print("scalf-opt: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # the reader closed the pipe (`scalf-opt optimize | head`): stop quietly; point stdout at
        # /dev/null so that Python's own flush at exit does not fail again
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141
