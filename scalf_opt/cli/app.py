"""Parse the command line, dispatch to a command, and turn failures into one line and a code.

Exit codes: 0 success; 1 an unexpected failure (a bug: one line and a hint, ``--debug`` shows the
traceback); 2 bad input (:class:`~scalf_opt.errors.ScalfError`: one line on stderr naming the file
or field; also an optional part the command needs that is not installed, naming its extra); 3 an
optimizer did not converge (the command says which); 130 interrupted (Ctrl-C); 143 terminated
(SIGTERM; both remove the temporary files first); 141 the reader of the output went away where a
command could not go on without it (normally a closed pipe only drops the rest of the output: the
command finishes and writes its files).
"""

from __future__ import annotations

import argparse
import errno
import importlib.metadata
import os
import re
import sys
import warnings
from collections.abc import Sequence
from typing import Any, NoReturn

from scalf_opt.cli.commands import COMMANDS
from scalf_opt.cli.console import Console, terminal_safe
from scalf_opt.cli.options import default_outputs
from scalf_opt.errors import ScalfError, close_matches, did_you_mean, suggestion
from scalf_opt.files import output_set, remove_stale_scratch
from scalf_opt.interrupts import raise_if_stopped, stop_code, stop_on_signals
from scalf_opt.version import __version__


class _StoreOnce(argparse._StoreAction):
    """An option that takes one value: given twice is an error, not the last value kept."""

    def __call__(
        self,
        parser: argparse.ArgumentParser,
        namespace: argparse.Namespace,
        values: str | Sequence[Any] | None,
        option_string: str | None = None,
    ) -> None:
        given = namespace.__dict__.setdefault("_options_given", set())
        if self.dest in given:
            raise argparse.ArgumentError(self, "given more than once: give it once")
        given.add(self.dest)
        super().__call__(parser, namespace, values, option_string)


class Parser(argparse.ArgumentParser):
    """argparse with its errors on one line: what is wrong, a close match, where help is.

    An option that takes one value may be given once (argparse keeps the last silently).
    """

    def __init__(self, *args: object, **kwargs: object) -> None:
        super().__init__(*args, **kwargs)  # type: ignore[arg-type]
        self.register("action", None, _StoreOnce)
        self.register("action", "store", _StoreOnce)

    def error(self, message: str) -> NoReturn:
        """Print ``scalf-opt: error: ...`` on one line and exit with code 2."""
        hint = ""
        choice = re.search(r"invalid choice: '([^']*)' \(choose from (.*)\)", message)
        unknown = re.match(r"unrecognized arguments: (\S+)", message)
        if choice:
            hint = did_you_mean(choice.group(1), re.findall(r"'([^']*)'", choice.group(2)))
        elif unknown:
            # names compared without their dashes, which every flag shares: '--method' is no
            # near miss of '--period'
            options = {o.lstrip("-"): o for action in self._actions for o in action.option_strings}
            close = close_matches(unknown.group(1).lstrip("-"), options)
            hint = suggestion(options[name] for name in close)
        line = terminal_safe(" ".join(f"{message}{hint}".splitlines()))
        sys.stderr.write(f"scalf-opt: error: {line} (see {self.prog} --help)\n")
        sys.exit(2)


def _naming_the_option(exc: ScalfError, parser: argparse.ArgumentParser, argv: list[str]) -> str:
    """The error's message, led by the option the user gave for the field it is about."""
    message = str(exc)
    if exc.field is None or message.startswith("--"):
        return message
    option = "--" + exc.field.replace("_", "-")
    given = any(a == option or a.startswith(option + "=") for a in argv)
    known = any(option in action.option_strings for action in parser._actions)
    return f"{option}: {message}" if given and known else message


def _common_options(with_json: bool, with_verbose: bool) -> Parser:
    common = Parser(add_help=False)
    group = common.add_argument_group("output")
    if with_json:
        group.add_argument(
            "--json",
            action="store_true",
            help="print the results as JSON on stdout instead of text",
        )
    group.add_argument(
        "-q", "--quiet", action="store_true", help="print nothing but errors (files are written)"
    )
    if with_verbose:
        group.add_argument(
            "-v", "--verbose", action="store_true", help="show the solvers' own logs (Ipopt's)"
        )
    group.add_argument(
        "--debug", action="store_true", help="show the traceback of an unexpected failure"
    )
    return common


def _examples(examples: Sequence[tuple[str, str]]) -> str:
    """The ``--help`` epilog: each example command line and what it does."""
    lines = ["examples:"]
    for line, what in examples:
        lines += [f"  {line}", f"      {what}"]
    return "\n".join(lines)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of every command."""
    parser = Parser(
        prog="scalf-opt",
        description="Energy-efficient swing-foot trajectories for legged robots (SCalf paper).",
    )
    parser.add_argument("--version", action="version", version=f"scalf-opt {__version__}")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    parser.set_defaults(commands={})
    for command in COMMANDS:
        p = sub.add_parser(
            command.NAME,
            help=command.HELP,
            description=command.HELP,
            epilog=_examples(command.EXAMPLES),
            formatter_class=argparse.RawDescriptionHelpFormatter,
            parents=[
                _common_options(getattr(command, "JSON", False), getattr(command, "VERBOSE", False))
            ],
        )
        command.add_arguments(p)
        p.set_defaults(run=command.run, outputs=getattr(command, "outputs", None))
        parser.get_default("commands")[command.NAME] = p
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``scalf-opt`` console script."""
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = build_parser()
    args, extra = parser.parse_known_args(argv)
    if extra:  # reported by the command's own parser, which knows its options
        args.commands[args.command].error(f"unrecognized arguments: {' '.join(extra)}")
    args.argv = ["scalf-opt", *argv]
    args.verbose = getattr(args, "verbose", False)
    console = Console(quiet=args.quiet, json_output=getattr(args, "json", False))
    args.console = console
    try:
        with stop_on_signals():
            return _run(args, argv, console)
    except KeyboardInterrupt:  # a second Ctrl-C while the first one's cleanup ran
        return 130


def _with_warnings(args: argparse.Namespace) -> int:
    """Run the command with the numerical libraries' warnings caught, not printed.

    NumPy's and SciPy's warnings (an overflow in an intermediate value, say) would print
    several lines with install paths before the one-line error; they are shown, one line
    each, only with ``--verbose`` when the command succeeds.
    """
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("default")
        code = _run_in_output_set(args)
    if caught and getattr(args, "verbose", False):
        for warning in caught:
            args.console.note(f"warning: {warning.category.__name__}: {warning.message}")
    return code


def _run_in_output_set(args: argparse.Namespace) -> int:
    """Run the command; the files it writes to its outputs are moved into place together."""
    remove_stale_scratch()  # what killed runs left in the temporary folder
    outputs = args.outputs(args) if args.outputs is not None else default_outputs(args)
    if outputs is None:
        return int(args.run(args))
    outputs.check()
    with output_set(outputs.folders.values(), outputs.files.values(), outputs.direct):
        code = int(args.run(args))
        raise_if_stopped()  # a signal some library swallowed: nothing is moved into place
        return code


def _run(args: argparse.Namespace, argv: list[str], console: Console) -> int:
    try:
        code = _with_warnings(args)
        raise_if_stopped()  # a signal some library swallowed: the run's end is no success
        sys.stdout.flush()  # inside the try: a closed pipe surfaces here, not at exit
        return code
    except ScalfError as exc:
        console.error(_naming_the_option(exc, args.commands[args.command], argv))
        return 2
    except KeyboardInterrupt:
        console.error("interrupted")
        return 130
    except BrokenPipeError:
        # the reader closed the pipe (`scalf-opt optimize | head`): stop quietly; point stdout at
        # /dev/null so that Python's own flush at exit does not fail again
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 141
    except ModuleNotFoundError as exc:
        missing = missing_extra(exc)
        if missing is None:
            return _unexpected(args, exc, console)
        package, extra = missing
        console.error(
            f"{package} is not installed: scalf-opt {args.command} needs the optional "
            f"'{extra}' part (make install in a clone of scalf-opt, which installs every part at "
            f"the pinned versions; else pip install 'scalf-opt[{extra}]')"
        )
        return 2
    except OSError as exc:
        if exc.filename is not None and exc.errno in _PATH_ERRORS:
            console.error(f"{exc.filename}: {exc.strerror}")  # a path the system refuses
            return 2
        return _unexpected(args, exc, console)
    except Exception as exc:
        return _unexpected(args, exc, console)


_PATH_ERRORS = frozenset(
    {
        errno.ENAMETOOLONG,
        errno.EACCES,
        errno.EPERM,
        errno.ENOSPC,
        errno.EDQUOT,
        errno.EROFS,
        errno.ELOOP,
        errno.ENOTDIR,
        errno.EISDIR,
        errno.ENOENT,
        errno.EFBIG,
    }
)
"""What the system says of a path the user gave (too long, denied, full, read-only, a loop): bad
input naming the path, wherever in a library it surfaced."""


def missing_extra(exc: ModuleNotFoundError) -> tuple[str, str] | None:
    """The package ``exc`` did not find, and the extra of scalf-opt that provides it (if one does).

    Read from the installed package's metadata (``pyproject.toml``'s optional dependencies), so
    that a command of an optional part (``simulate``: MuJoCo; ``view``: meshcat) run without it
    says what to install instead of reporting a bug.
    """
    module = (exc.name or "").split(".")[0].lower()
    try:
        requirements = importlib.metadata.requires("scalf-opt") or []
    except importlib.metadata.PackageNotFoundError:
        return None
    for requirement in requirements:
        match = re.match(r"\s*([A-Za-z0-9_.-]+).*;\s*extra\s*==\s*['\"]([\w-]+)['\"]", requirement)
        if match and re.sub(r"[-.]", "_", match[1].lower()) == module:
            return module, match[2]
    return None


def _unexpected(args: argparse.Namespace, exc: Exception, console: Console) -> int:
    """A bug (exit 1), unless a library turned a signal into this error (130, 143)."""
    stopped = stop_code()
    if stopped is not None:  # a library turned the signal's exception into its own error
        console.error("interrupted" if stopped == 130 else "terminated")
        return stopped
    if args.debug:
        raise exc
    console.error(
        f"unexpected failure: {type(exc).__name__}: {exc} (a bug: please report it; rerun "
        "with --debug for the traceback)"
    )
    return 1
