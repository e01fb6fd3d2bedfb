"""The Python examples of the README and of the documentation run as written (in a scratch
folder), so they cannot rot; the README stays a five-minute read."""

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
README = ROOT / "README.md"


def python_blocks(path: Path) -> list[str]:
    return re.findall(r"```python\n(.*?)```", path.read_text(encoding="utf-8"), re.DOTALL)


def test_the_readme_is_short():
    assert len(README.read_bytes()) <= 15_000


def test_the_readme_has_python_examples():
    assert python_blocks(README)


def test_the_readme_python_blocks_run(tmp_path, monkeypatch, capsys):
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    for block in python_blocks(README):
        exec(compile(block, str(README), "exec"), namespace)
    out = capsys.readouterr().out
    printed = re.search(r"It prints `([^`]*)`", README.read_text(encoding="utf-8"))
    assert printed and printed[1] in out  # what the README says it prints, it prints
    assert (tmp_path / "results" / "joint-6" / "summary.json").is_file()


@pytest.mark.slow  # a page's code end to end, a simulation: about 35 s alone
def test_the_python_api_page_runs(tmp_path, monkeypatch, capsys):
    page = ROOT / "docs" / "python-api.md"
    monkeypatch.chdir(tmp_path)
    namespace: dict = {}
    for block in python_blocks(page):
        exec(compile(block, str(page), "exec"), namespace)
    out = capsys.readouterr().out
    text = page.read_text(encoding="utf-8")
    printed = re.search(r"It prints `([^`]*)`", text)
    assert printed and printed[1] in out
    assert (tmp_path / "results" / "joint-6-sim" / "simulation.json").is_file()


def test_the_validation_numbers_are_the_referee_pages():
    """The README's validation summary quotes the referee page's generated tables (renewed by
    ``python docs/gen_outputs.py --manual docs/simulation-referee.md``) and its reading."""
    text = README.read_text(encoding="utf-8")
    section = text.split("## How far the energy model is validated")[1].split("\n## ")[0]
    page = (ROOT / "docs" / "simulation-referee.md").read_text(encoding="utf-8")
    quoted = re.findall(r"[-+]?\d+\.\d+ (?:%|points)", section)
    assert len(quoted) >= 12
    for number in quoted:
        value = number.split()[0]
        assert value in page, f"README quotes {number}, docs/simulation-referee.md has no {value}"


def test_the_gait_sweep_time_is_the_benchmark_s_page_not_a_typed_number():
    """The README's tour sends the reader to docs/gaits.md's run time, which its benchmark block
    measures (renewed by ``python docs/gen_outputs.py --manual docs/gaits.md``): it types no
    seconds of its own, which would go stale."""
    page = (ROOT / "docs" / "gaits.md").read_text(encoding="utf-8")
    assert "<!-- output manual: python benchmarks/bench_gait.py -->" in page
    tour = README.read_text(encoding="utf-8").split("## A five-command tour")[1].split("\n## ")[0]
    assert "docs/gaits.md#run-time" in tour and "benchmarks/bench_gait.py" in tour
    prose = tour.replace("\n", " ")
    assert not re.search(r"\b\d+(\.\d+)? s on\b", prose) and "times as long" not in prose
