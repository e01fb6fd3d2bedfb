"""Pinned installs: constraints.txt pins every package the project needs, at one version each,
and the environment the tests run in was installed from it (``make test`` does so)."""

import re
import tomllib
from importlib import metadata
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PINS = {}
for line in (ROOT / "constraints.txt").read_text().splitlines():
    if line.strip() and not line.startswith("#"):
        name, version = line.split("==")
        PINS[re.sub(r"[-_.]+", "-", name).lower()] = version.strip()


def requirement_names():
    project = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    requirements = list(project["dependencies"])
    for group in project["optional-dependencies"].values():
        requirements += group
    for requirement in requirements:
        name = re.match(r"[A-Za-z0-9_.-]+", requirement).group(0)
        if name != "scalf-opt":  # the `all` extra names the project's own extras
            yield re.sub(r"[-_.]+", "-", name).lower()


def test_every_dependency_is_pinned():
    missing = sorted(set(requirement_names()) - set(PINS))
    assert not missing, f"not in constraints.txt (run `make lock`): {missing}"


def test_the_environment_is_the_pinned_one():
    for name in sorted(set(requirement_names())):
        assert metadata.version(name) == PINS[name], name
