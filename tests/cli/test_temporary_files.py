"""Temporary files never outlive the command: not after success, an error, Ctrl-C or SIGTERM.

The runs below use a fresh compile cache, so that the command compiles (scratch folders, the C
compiler's own files) while it is stopped, and a study with a leg variant (a scratch URDF).
"""

import os
import signal
import subprocess
import sys
import time

import pytest

from scalf_opt.energy import codegen

STUDY = """\
[study]
robot = "scalf"
family = "paper"

[variant]
thigh_length_scale = 1.05
"""


def _start(tmp_path, *args):
    for name in ("tmp", "cache"):
        (tmp_path / name).mkdir()
    (tmp_path / "sweep.toml").write_text(STUDY)
    env = {
        **os.environ,
        "TMPDIR": str(tmp_path / "tmp"),
        "SCALF_OPT_CACHE": str(tmp_path / "cache"),
    }
    return subprocess.Popen(
        [sys.executable, "-m", "scalf_opt", *args],
        cwd=tmp_path,
        env=env,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )


def _leftovers(tmp_path):
    """Scratch files anywhere: the temporary folder, staged outputs, staged cache entries."""
    found = list((tmp_path / "tmp").iterdir())
    found += [p for p in tmp_path.rglob(".*") if p.is_file()]
    return found


def test_a_finished_study_leaves_no_temporary_file(tmp_path):
    proc = _start(tmp_path, "study", "sweep.toml", "--workers", "1", "--out", "out")
    _, err = proc.communicate(timeout=600)
    assert proc.returncode == 0, err
    assert (tmp_path / "out" / "results.csv").is_file()
    assert _leftovers(tmp_path) == []


def test_a_failed_command_leaves_no_temporary_file(tmp_path):
    proc = _start(tmp_path, "evaluate", "--period", "-1", "--out", "out")
    _, err = proc.communicate(timeout=600)
    assert proc.returncode == 2 and "period" in err
    assert _leftovers(tmp_path) == [] and not (tmp_path / "out").exists()


@pytest.mark.parametrize(("stop", "code"), [(signal.SIGINT, 130), (signal.SIGTERM, 143)])
def test_a_stopped_command_leaves_no_temporary_file(tmp_path, stop, code):
    if codegen._compiler() is None:
        pytest.skip("no C compiler: nothing is compiled, so there is nothing to stop mid-way")
    proc = _start(tmp_path, "study", "sweep.toml", "--workers", "1", "--out", "out")
    deadline = time.monotonic() + 300
    while not any((tmp_path / "tmp").iterdir()):  # stop it while it has scratch files
        assert proc.poll() is None, "finished before it made a temporary file"
        assert time.monotonic() < deadline
        time.sleep(0.01)
    time.sleep(0.3)  # into the compilation
    proc.send_signal(stop)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == code, err
    assert "Traceback" not in err
    assert _leftovers(tmp_path) == []


# A SIGINT while Python imports the command line (an import hook raises it as scalf_opt.cli.app
# is being imported), and one that arrives once the command's own handlers are removed (a
# stand-in command that raises it as it returns): both end with 130 and no traceback, as the
# console script and `python -m scalf_opt` run (scalf_opt.__main__.run). Before run() installed
# its handler first, the first printed a KeyboardInterrupt traceback and died of the signal (-2).
_EARLY = """
import importlib.abc, signal, sys

class Interrupt(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path, target=None):
        if name == "scalf_opt.cli.app":
            signal.raise_signal(signal.SIGINT)
        return None

sys.meta_path.insert(0, Interrupt())
from scalf_opt.__main__ import run
run()
"""

_LATE = """
import signal, sys
import scalf_opt.cli.app as app

def command(argv=None):
    signal.raise_signal(signal.SIGINT)  # outside every handler of the command line's own
    return 0

app.main = command
from scalf_opt.__main__ import run
run()
"""


@pytest.mark.parametrize("script", [_EARLY, _LATE], ids=["while importing", "as it returns"])
def test_ctrl_c_outside_a_command_exits_130_without_a_traceback(script):
    done = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=120
    )
    assert done.returncode == 130, done.stderr
    assert "Traceback" not in done.stderr


# Ctrl-C while a command runs source text (a dataclass, a named tuple or an enum being created,
# as a module is imported): CPython took a KeyboardInterrupt that left such code for an
# unhandled ^C, and under `python -m` ended the interpreter by SIGINT at exit although the
# command had printed its one line and returned 130 (return code -2, about once in a hundred
# interruptions of a study's first imports). The command line raises a subclass instead.
_IN_SOURCE_TEXT = """
import scalf_opt.cli.app as app

def run_in_output_set(args):
    exec("import signal\\nsignal.raise_signal(signal.SIGINT)\\nfor _ in range(1000): pass")
    return 0

app._run_in_output_set = run_in_output_set
from scalf_opt.__main__ import run
run()
"""


def test_ctrl_c_in_source_text_exits_130_under_python_m(tmp_path):
    (tmp_path / "ctrl_c_in_source_text.py").write_text(_IN_SOURCE_TEXT)
    done = subprocess.run(
        [sys.executable, "-m", "ctrl_c_in_source_text", "evaluate"],
        cwd=tmp_path,
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert done.returncode == 130, done.stderr
    assert done.stderr.strip() == "scalf-opt: error: interrupted"


def test_a_gait_stopped_with_its_workers_leaves_no_temporary_file(tmp_path):
    """SIGTERM to ``gait --workers 2``: its workers are killed, their scratch folders removed."""
    if len(os.sched_getaffinity(0)) < 2:
        pytest.skip("two workers need two usable cores")
    argv = ["gait", "--robot", "scalf", "--speed", "0.8:1.0:0.2", "--workers", "2", "--out", "g"]
    proc = _start(tmp_path, *argv)
    deadline = time.monotonic() + 300
    while len(list((tmp_path / "tmp").glob("scalf-opt-case-*"))) < 2:  # both workers at work
        assert proc.poll() is None, "finished before its workers made their scratch folders"
        assert time.monotonic() < deadline
        time.sleep(0.05)
    proc.send_signal(signal.SIGTERM)
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == 143, err
    assert "Traceback" not in err
    assert _leftovers(tmp_path) == [] and not (tmp_path / "g").exists()
