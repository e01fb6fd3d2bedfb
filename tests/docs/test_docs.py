"""The documentation site builds offline with ``--strict`` (a broken link, a missing heading or an
API page whose object does not resolve fails), every page is in the navigation, every public API
name has its reference page, and every command output embedded in a page is what the command
prints now (``docs/gen_outputs.py``)."""

import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

import scalf_opt.api
from docs import gen_outputs

ROOT = Path(__file__).resolve().parents[2]
DOCS = ROOT / "docs"

pytest.importorskip("mkdocs")
pytest.importorskip("mkdocstrings")


def test_the_site_builds_strictly_offline(tmp_path):
    env = {**os.environ, "NO_MKDOCS_2_WARNING": "1"}
    proc = subprocess.run(
        [sys.executable, "-m", "mkdocs", "build", "--strict", "--site-dir", str(tmp_path / "site")],
        cwd=ROOT,
        capture_output=True,
        text=True,
        env=env,
        check=False,
    )
    assert proc.returncode == 0, proc.stderr
    html = (tmp_path / "site" / "index.html").read_text(encoding="utf-8")
    assert "fonts.googleapis" not in html  # theme.font: false, nothing fetched for the pages
    reference = (tmp_path / "site" / "reference" / "evaluation.html").read_text(encoding="utf-8")
    assert 'id="scalf_opt.api.evaluation.evaluate"' in reference  # generated from the docstring


def nav_pages(config: str) -> set[str]:
    return set(re.findall(r"([\w/-]+\.md)", config))


def test_every_page_is_in_the_navigation():
    config = (ROOT / "mkdocs.yml").read_text(encoding="utf-8")
    pages = {p.relative_to(DOCS).as_posix() for p in DOCS.rglob("*.md")}
    assert pages == nav_pages(config)


def test_every_public_api_name_has_a_reference_page():
    documented = set()
    for page in (DOCS / "reference").glob("*.md"):
        documented |= set(re.findall(r"^::: ([\w.]+)$", page.read_text(), re.MULTILINE))
    for name in scalf_opt.api.__all__:
        module = getattr(scalf_opt.api, name).__module__
        assert module in documented, f"{name} ({module}) has no API reference page"


def test_the_readme_links_only_to_pages_that_exist():
    text = (ROOT / "README.md").read_text(encoding="utf-8")
    for target in re.findall(r"\]\(((?:docs|examples)/[^)#]+)", text):
        assert (ROOT / target).exists(), target


def pages_with_outputs(slow: bool) -> list[Path]:
    return [
        page
        for page in gen_outputs.pages()
        if any(b.slow == slow for b in gen_outputs.blocks(page.read_text(encoding="utf-8")))
    ]


def stale(page: Path, fast: bool, slow_only: bool = False) -> list[str]:
    _, changed = gen_outputs.regenerate(page, fast=fast, slow_only=slow_only)
    return [f"{block.command}:\n{renewed}" for block, renewed in changed]


@pytest.mark.parametrize("page", pages_with_outputs(slow=False), ids=lambda p: p.name)
def test_embedded_outputs_are_what_the_commands_print(page):
    assert not stale(page, fast=True), "stale: run python docs/gen_outputs.py"


@pytest.mark.slow
@pytest.mark.parametrize("page", pages_with_outputs(slow=True), ids=lambda p: p.name)
def test_embedded_outputs_of_slow_commands(page):
    """The slow blocks alone: the test above checks the others."""
    assert not stale(page, fast=False, slow_only=True), "stale: run python docs/gen_outputs.py"


def test_a_stale_output_is_found(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(
        "<!-- output: scalf-opt model | head -1 -->\n```console\n$ scalf-opt model\nold\n```\n"
    )
    assert stale(page, fast=True)


def test_the_slow_check_runs_the_slow_blocks_alone(tmp_path):
    page = tmp_path / "page.md"
    page.write_text(
        "<!-- output: scalf-opt model | head -1 -->\n```console\n$ scalf-opt model\nold\n```\n"
        "<!-- output slow: scalf-opt model --robot hyq | head -1 -->\n"
        "```console\n$ scalf-opt model --robot hyq\nold\n```\n"
    )
    assert [s.split(":\n")[0] for s in stale(page, fast=False, slow_only=True)] == [
        "scalf-opt model --robot hyq | head -1"
    ]
    assert [s.split(":\n")[0] for s in stale(page, fast=True)] == ["scalf-opt model | head -1"]


def test_a_marked_figure_is_drawn_again_by_its_command(tmp_path):
    # a figure's image is the file its command writes (drawn again with --manual; never
    # compared by the tests, whose machines' BLAS and fonts change a PNG's bytes)
    page = tmp_path / "page.md"
    page.write_text(
        "Text.\n\n<!-- figure: scalf-opt evaluate --out ev :: ev/summary.json -->\n"
        "![the reference's summary](summary.json)\n"
    )
    (tmp_path / "summary.json").write_text("stale")
    assert gen_outputs.figures(page.read_text()) == [
        gen_outputs.Figure("scalf-opt evaluate --out ev", "ev/summary.json", "summary.json")
    ]
    skipped: list[Path] = []
    assert gen_outputs.regenerate(page, only="model", drawn=skipped) == (page.read_text(), [])
    assert skipped == [] and (tmp_path / "summary.json").read_text() == "stale"
    drawn: list[Path] = []
    assert gen_outputs.regenerate(page, drawn=drawn) == (page.read_text(), [])
    assert drawn == [tmp_path / "summary.json"]
    assert json.loads(drawn[0].read_text())["provenance"]["robot"] == "scalf"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["page.md", "summary.json"]


def test_a_figure_drawn_by_a_blocks_command_is_not_run_again(tmp_path, monkeypatch):
    # gaits.md's figures come from the minutes-long `gait` runs its blocks show: one run each
    page = tmp_path / "page.md"
    page.write_text(
        "<!-- output: scalf-opt evaluate --out ev | head -1 -->\n```console\nold\n```\n\n"
        "<!-- figure: scalf-opt evaluate --out ev :: ev/summary.json -->\n"
        "![the reference's summary](summary.json)\n"
    )
    runs = []
    execute = gen_outputs.execute
    monkeypatch.setattr(gen_outputs, "execute", lambda *a: runs.append(a[0]) or execute(*a))
    drawn: list[Path] = []
    _, changed = gen_outputs.regenerate(page, drawn=drawn)
    assert runs == ["scalf-opt evaluate --out ev | head -1"]
    assert len(changed) == 1 and drawn == [tmp_path / "summary.json"]
    assert json.loads(drawn[0].read_text())["provenance"]["robot"] == "scalf"
