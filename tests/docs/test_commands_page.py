"""The commands page lists every command the parser has: a row of its table and a section with
the command's own ``--help`` (renewed from the parser by ``docs/gen_outputs.py``), so that a new
command cannot be left out."""

import re
from pathlib import Path

from scalf_opt.cli.commands import COMMANDS

PAGE = Path(__file__).resolve().parents[2] / "docs" / "commands.md"


def test_every_command_has_a_row_and_its_help():
    text = PAGE.read_text(encoding="utf-8")
    rows = re.findall(r"^\| \[`([a-z-]+)`\]\(#\1\) \|", text, re.MULTILINE)
    sections = re.findall(r"^### ([a-z-]+)\n\n<!-- output: scalf-opt \1 --help -->", text, re.M)
    names = [command.NAME for command in COMMANDS]
    assert rows == names  # in the order of `scalf-opt --help`
    assert sorted(sections) == sorted(names)
