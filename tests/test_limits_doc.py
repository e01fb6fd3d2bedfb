"""docs/limits.md states every bound with the number the code holds (each row is checked)."""

import importlib
import re
import subprocess
import sys
from pathlib import Path

import pytest

DOC = Path(__file__).resolve().parents[1] / "docs" / "limits.md"
TEXT = DOC.read_text(encoding="utf-8")
CONSTANTS = re.findall(r"`(scalf_opt(?:\.\w+)+)\.([A-Z_]+) = ([^`]+)`", TEXT)
HELPS = re.findall(r"help of `scalf-opt (\S+)`: `([^`]+)`", TEXT)


def test_the_page_names_its_bounds():
    assert len(CONSTANTS) >= 35 and len(HELPS) >= 4


@pytest.mark.parametrize(("module", "name", "value"), CONSTANTS, ids=[c[1] for c in CONSTANTS])
def test_each_stated_bound_is_the_codes(module, name, value):
    assert getattr(importlib.import_module(module), name) == float(value)


@pytest.mark.parametrize(("command", "text"), HELPS, ids=[f"{c} {t}" for c, t in HELPS])
def test_each_stated_option_range_is_in_its_help(command, text):
    out = subprocess.run(
        [sys.executable, "-m", "scalf_opt", command, "--help"],
        capture_output=True,
        text=True,
        check=True,
        env={"COLUMNS": "1000", "PATH": ""},
    ).stdout
    assert text in out


def test_every_upper_bound_of_an_option_is_in_the_page():
    from scalf_opt.cli.app import build_parser

    parser = build_parser()
    for command, sub in parser.get_default("commands").items():
        for action in sub._actions:
            bound = getattr(action.type, "__qualname__", "").startswith("bounded.")
            if bound:
                assert f"`{action.option_strings[-1]}" in TEXT or any(
                    o in TEXT for o in action.option_strings
                ), (command, action.option_strings)


def test_the_command_lines_copy_of_a_bound_is_the_apis():
    from scalf_opt.cli.commands import export
    from scalf_opt.io import plan_export

    assert export.MAX_CYCLES == plan_export.MAX_CYCLES
    assert export.FORMATS == plan_export.EXPORT_FORMATS  # the registry's suffixes
