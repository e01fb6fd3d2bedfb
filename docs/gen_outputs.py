"""Regenerate the command outputs embedded in the documentation, so that no number is typed.

A block of command output in a page (or the README) is marked by the command that printed it::

    <!-- output: scalf-opt evaluate --robot hyq | head -12 -->
    ```console
    $ scalf-opt evaluate --robot hyq | head -12
    ... what it printed ...
    ```

``<!-- output slow: ... -->`` marks a command that takes more than a few seconds (the tests re-run
it only with the ``slow`` ones); ``<!-- output manual: ... -->`` one that takes minutes (renewed
only with ``--manual``; no test re-runs it). The commands of one page run in order in one scratch
folder, so a later command can read what an earlier one wrote (``optimize --out`` then
``simulate --from``); ``examples/`` is there too. ``scalf-opt`` is this interpreter's
``python -m scalf_opt``,
``python`` this interpreter (a script path is taken from the repository). ``| head -N`` keeps
the first N lines, ``| tail -N`` the last N. ``<!-- output markdown: ... -->`` marks a command
that prints Markdown (tables), embedded as it is up to ``<!-- end of output -->``.

A figure of a page is marked by the command that draws it and the file it writes there::

    <!-- figure: scalf-opt figures --format png --out figs :: figs/foot_paths.png -->
    ![Foot paths ...](foot_paths.png)

With ``--manual`` the command runs in the page's scratch folder after its blocks (once per page:
not again when a block of the page ran it) and the file replaces the image the next line shows;
``--check`` leaves figures alone (a PNG's bytes differ between machines' BLAS and fonts, so the
tests cannot compare them).

Usage: ``python docs/gen_outputs.py [--check] [--fast] [--manual] [--only TEXT] [FILE.md ...]``
(default: the README and every page). ``--check`` changes nothing and exits 1 when a block differs
from what its command prints now; ``--fast`` leaves out the ``slow`` commands; ``--only TEXT``
runs only the blocks whose command contains TEXT (one benchmark of a page, or a command and the
one that reads what it wrote).
"""

from __future__ import annotations

import argparse
import os
import re
import shlex
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
RUN_TIME = re.compile(r"(iterations, |in |took |tried, )\d+(\.\d+)? s\b")
"""A run time in an output: it never repeats, so blocks are compared without it."""
MARKER = re.compile(
    r"<!-- output(?P<slow> slow| manual)?(?P<markdown> markdown)?: (?P<command>[^\n]*?) -->\n"
    r"(?:```console\n(?P<body>.*?)```\n|(?P<text>.*?)<!-- end of output -->\n)",
    re.DOTALL,
)

FIGURE = re.compile(
    r"<!-- figure: (?P<command>[^\n]*?) :: (?P<made>\S+) -->\n!\[[^\]]*\]\((?P<target>[^)\s]+)\)"
)


@dataclass(frozen=True)
class Figure:
    """One marked figure of a page: the command, the file it writes, the image shown."""

    command: str
    made: str
    target: str


def figures(text: str) -> list[Figure]:
    """The marked figures of a page, in order."""
    return [Figure(m["command"], m["made"], m["target"]) for m in FIGURE.finditer(text)]


@dataclass(frozen=True)
class Block:
    """One marked output block of a page."""

    command: str
    slow: bool
    markdown: bool
    manual: bool
    body: str
    start: int
    end: int


def blocks(text: str) -> list[Block]:
    """The marked output blocks of a page, in order."""
    return [
        Block(
            m["command"],
            bool(m["slow"]),
            bool(m["markdown"]),
            m["slow"] == " manual",
            m["text"] if m["markdown"] else m["body"],
            m.start(),
            m.end(),
        )
        for m in MARKER.finditer(text)
    ]


def pages() -> list[Path]:
    """The README and every documentation page."""
    return [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]


def _argv(command: str) -> tuple[list[str], int | None]:
    head = None
    if "|" in command:
        command, tail = (part.strip() for part in command.split("|", 1))
        match = re.fullmatch(r"(head|tail) -(\d+)", tail)
        if not match:
            raise ValueError(f"only '| head -N' or '| tail -N' may follow a command: {tail!r}")
        head = int(match[2]) if match[1] == "head" else -int(match[2])
    words = shlex.split(command)
    if words[0] == "scalf-opt":
        argv = [sys.executable, "-m", "scalf_opt", *words[1:]]
    elif words[0] == "python":
        script = ROOT / words[1]
        argv = [sys.executable, str(script if script.is_file() else words[1]), *words[2:]]
    else:
        raise ValueError(f"a documented command starts with scalf-opt or python: {command!r}")
    return argv, head


def run(
    command: str, cwd: Path, markdown: bool = False, printed: dict[str, str] | None = None
) -> str:
    """What ``command`` prints in ``cwd``, as the block shows it.

    A console block shows the command's line, then its output; a Markdown block (a command that
    prints Markdown tables) the output alone, its headings as bold lines, without the ``wrote``
    line. ``printed`` keeps each command's output for the next block that shows the same command
    (another part of its output), so that it runs once per page.
    """
    argv, head = _argv(command)
    key = shlex.join(argv)
    if printed is None or key not in printed:
        stdout = execute(command, argv, cwd)
        if printed is not None:
            printed[key] = stdout
    else:
        stdout = printed[key]
    lines = stdout.splitlines()
    if markdown:
        lines = [line for line in lines if not line.startswith("wrote ")]
    if head is not None:
        lines = lines[:head] if head >= 0 else lines[head:]
    if markdown:
        lines = [re.sub(r"^#+ (.*)$", r"**\1**", line) for line in lines]
        return "\n".join(lines).strip("\n") + "\n"
    return "\n".join([f"$ {command}", *lines]) + "\n"


def execute(command: str, argv: list[str], cwd: Path) -> str:
    """Run a documented command in ``cwd``; what it printed (an error if it failed)."""
    env = {**os.environ, "MPLBACKEND": "Agg", "COLUMNS": "100", "PYTHONPATH": str(ROOT)}
    proc = subprocess.run(argv, cwd=cwd, capture_output=True, text=True, env=env, check=False)
    if proc.returncode not in (0, 3):
        raise RuntimeError(f"{command} exited {proc.returncode}: {proc.stderr.strip()}")
    return proc.stdout


def draw_figures(
    page: Path, scratch: Path, only: str | None = None, printed: dict[str, str] | None = None
) -> list[Path]:
    """Draw the page's marked figures in ``scratch`` and replace their images.

    A command that ``printed`` holds already ran in ``scratch`` (a block of the page shows its
    output, ``| head`` aside) and is not run again; each other command runs once.
    """
    printed = {} if printed is None else printed
    renewed: list[Path] = []
    for figure in figures(page.read_text(encoding="utf-8")):
        if only is not None and only not in figure.command:
            continue
        argv, head = _argv(figure.command)
        if head is not None:
            raise ValueError(f"a figure's command prints nothing to keep: {figure.command}")
        key = shlex.join(argv)
        if key not in printed:
            printed[key] = execute(figure.command, argv, scratch)
        made = scratch / figure.made
        if not made.is_file():
            raise RuntimeError(f"{figure.command} did not write {figure.made}")
        target = page.parent / figure.target
        partial = target.with_name(f".{target.name}.partial")
        partial.write_bytes(made.read_bytes())
        os.replace(partial, target)
        renewed.append(target)
    return renewed


def same_output(a: str, b: str) -> bool:
    """Whether two outputs are the same but for run times."""
    return RUN_TIME.sub(r"\1<time> s", a) == RUN_TIME.sub(r"\1<time> s", b)


def regenerate(
    page: Path,
    fast: bool = False,
    manual: bool = False,
    only: str | None = None,
    slow_only: bool = False,
    drawn: list[Path] | None = None,
) -> tuple[str, list[tuple[Block, str]]]:
    """The page with every block's output renewed, and the blocks whose output changed.

    ``fast`` leaves out the ``slow`` and ``manual`` commands; ``manual`` ones (minutes long) run
    only when ``manual`` is true; ``slow_only`` runs the ``slow`` ones alone (the tests check the
    others apart, and no slow block reads what a fast one writes); with ``only``, just the
    blocks whose command contains it. With ``drawn`` (a list), the page's marked figures are
    drawn again too, after its blocks and in the same folder (a figure whose command a block
    ran is taken from that run), and their images listed there.
    """
    text = page.read_text(encoding="utf-8")
    changed: list[tuple[Block, str]] = []
    pieces: list[str] = []
    printed: dict[str, str] = {}
    last = 0
    with tempfile.TemporaryDirectory(prefix="scalf-opt-docs-") as scratch:
        (Path(scratch) / "examples").symlink_to(ROOT / "examples")  # the inputs pages refer to
        for block in blocks(text):
            pieces.append(text[last : block.start])
            last = block.end
            body = block.body
            skipped = (
                (fast and block.slow)
                or (block.manual and not manual)
                or (slow_only and not block.slow)
            )
            if not skipped and (only is None or only in block.command):
                renewed = run(block.command, Path(scratch), block.markdown, printed)
                if not same_output(renewed, block.body):
                    changed.append((block, renewed))
                    body = renewed
            kind = (" manual" if block.manual else " slow" if block.slow else "") + (
                " markdown" if block.markdown else ""
            )
            if block.markdown:
                pieces.append(
                    f"<!-- output{kind}: {block.command} -->\n{body}<!-- end of output -->\n"
                )
            else:
                pieces.append(f"<!-- output{kind}: {block.command} -->\n```console\n{body}```\n")
        if drawn is not None:
            drawn += draw_figures(page, Path(scratch), only, printed)
    pieces.append(text[last:])
    return "".join(pieces), changed


def main() -> int:
    """Regenerate (or check) the pages given, or all of them."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("pages", nargs="*", type=Path)
    parser.add_argument("--check", action="store_true", help="change nothing; exit 1 on a diff")
    parser.add_argument("--fast", action="store_true", help="leave out the slow commands")
    parser.add_argument(
        "--manual", action="store_true", help="also run the manual ones (minutes each)"
    )
    parser.add_argument("--only", metavar="TEXT", help="only the commands containing TEXT")
    args = parser.parse_args()
    stale = 0
    for page in args.pages or pages():
        draw = args.manual and not args.check
        drawn: list[Path] = []
        marked = page.read_text(encoding="utf-8")
        if not blocks(marked) and not (draw and figures(marked)):
            continue
        text, changed = regenerate(
            page,
            fast=args.fast,
            manual=args.manual,
            only=args.only,
            drawn=drawn if draw else None,
        )
        for target in drawn:
            print(f"{page}: {target.name}: drawn again")
        for block, _ in changed:
            print(f"{page}: {block.command}: {'differs' if args.check else 'renewed'}")
        stale += len(changed)
        if changed and not args.check:
            page.write_text(text, encoding="utf-8")
    return 1 if args.check and stale else 0


if __name__ == "__main__":
    sys.exit(main())
