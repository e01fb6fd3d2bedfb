"""Every function of the package stays readable: cyclomatic complexity at most 20 (radon's
count: one plus each branch, loop, boolean operator and comprehension), at most 120 lines."""

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2] / "scalf_opt"
MAX_COMPLEXITY = 20
MAX_LINES = 120


def _modules():
    return sorted(PACKAGE.rglob("*.py"))


def test_no_function_is_too_branchy():
    radon = pytest.importorskip("radon.complexity")
    too = [
        f"{path.relative_to(PACKAGE.parent)}:{block.lineno} {block.name} ({block.complexity})"
        for path in _modules()
        for block in radon.cc_visit(path.read_text(encoding="utf-8"))
        if block.complexity > MAX_COMPLEXITY
    ]
    assert not too, "\n".join(too)


def test_no_function_is_too_long():
    too = [
        f"{path.relative_to(PACKAGE.parent)}:{node.lineno} {node.name} "
        f"({node.end_lineno - node.lineno + 1} lines)"
        for path in _modules()
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8")))
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef)
        and node.end_lineno - node.lineno + 1 > MAX_LINES
    ]
    assert not too, "\n".join(too)
