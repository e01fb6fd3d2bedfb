"""Command runs that tests of several modules read, each made once per worker.

The tests that read them are in the xdist group ``cli_runs`` (one worker), so that each run is
made once in the suite.
"""

import contextlib
import io
import json

import pytest

from scalf_opt.cli import main

GAIT_ARGV = ("gait", "--speed", "1.0", "--family", "paper", "--workers", "1", "--loads", "trunk")
"""docs/gaits.md's loads: under the default whole-body loads the search takes minutes."""


@pytest.fixture(scope="session")
def gait_run(tmp_path_factory):
    """``scalf-opt gait`` (:data:`GAIT_ARGV`, ``-q``): its folder and exit code. A later run into
    the same folder reads its cases from the folder's cache."""
    out = tmp_path_factory.mktemp("gait")
    return out, main([*GAIT_ARGV, "--out", str(out), "-q"])


@pytest.fixture(scope="session")
def simulated(tmp_path_factory):
    """``scalf-opt simulate --cycles 3 --out DIR --log DIR/log.csv --json``: DIR and the JSON it
    printed. Three cycles: the log then holds a complete cycle from a touch-down for every leg."""
    pytest.importorskip("mujoco")
    out = tmp_path_factory.mktemp("sim")
    argv = ["simulate", "--cycles", "3", "--out", str(out), "--log", str(out / "log.csv")]
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        assert main([*argv, "--json"]) == 0
    return out, json.loads(printed.getvalue())
