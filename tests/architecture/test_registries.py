"""Solvers and accountings are chosen through their registries, never by comparing names.

A new solver or accounting is one class and one registry line: nothing else in the package may
branch on a method's or an accounting's name (``if method == "ipopt"``), or the new entry would
be silently treated as one of the old ones there.
"""

import ast
from pathlib import Path

import pytest

from scalf_opt.energy.accounting import ACCOUNTINGS, accounting
from scalf_opt.errors import ConfigError
from scalf_opt.optimize.solvers import DEFAULT_SOLVER, SOLVERS, solver

PACKAGE = Path(__file__).resolve().parents[2] / "scalf_opt"
REGISTRIES = {PACKAGE / "energy" / "accounting.py", PACKAGE / "optimize" / "solvers.py"}
CHOSEN = ("method", "accounting")


def _name(node: ast.AST) -> str | None:
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        return node.attr
    return None


def name_comparisons(path: Path) -> list[str]:
    """``x == "..."`` / ``x in ("...",)`` where ``x`` is called method or accounting."""
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if not isinstance(node, ast.Compare):
            continue
        sides = [node.left, *node.comparators]
        named = [n for n in map(_name, sides) if n is not None]
        literal = any(
            (isinstance(s, ast.Constant) and isinstance(s.value, str))
            or isinstance(s, ast.Tuple | ast.List | ast.Set)
            for s in sides
        )
        if literal and any(n.endswith(CHOSEN) for n in named):
            found.append(f"{path.relative_to(PACKAGE)}:{node.lineno}")
    return found


def test_no_solver_or_accounting_is_chosen_by_its_name_outside_its_registry():
    offenders = [
        hit
        for path in sorted(PACKAGE.rglob("*.py"))
        if path not in REGISTRIES
        for hit in name_comparisons(path)
    ]
    assert offenders == []


def test_the_check_finds_a_comparison(tmp_path):
    sample = PACKAGE / "_probe_for_the_test.py"
    try:
        sample.write_text('def f(method):\n    return method == "ipopt"\n')
        assert name_comparisons(sample) == ["_probe_for_the_test.py:2"]
    finally:
        sample.unlink()


def test_the_registries_name_their_entries_and_refuse_unknown_names():
    assert list(ACCOUNTINGS) == ["paper", "positive", "regenerative"]
    assert DEFAULT_SOLVER == "ipopt" and set(SOLVERS) == {"ipopt", "pattern"}
    for name, entry in ACCOUNTINGS.items():
        assert accounting(name) is entry and entry.name == name
    for name, entry in SOLVERS.items():
        assert solver(name) is entry and entry.name == name
    with pytest.raises(ConfigError, match="positive"):
        accounting("absolute")
    with pytest.raises(ConfigError, match="pattern"):
        solver("free")  # the free-trajectory bound is a family ("free"), not a solver


def test_the_command_line_offers_the_registries(capsys):
    from scalf_opt.cli.app import build_parser

    parser = build_parser()
    optimize = parser.get_default("commands")["optimize"]
    text = optimize.format_help()
    for name, entry in SOLVERS.items():
        assert name in text and entry.description.split()[0] in text
    for name in ACCOUNTINGS:
        assert name in text
