"""Long work is never silent: a heartbeat on stderr when the output is not a terminal."""

import time

from scalf_opt.cli.progress import ProgressBar
from scalf_opt.heartbeat import Heartbeat


def test_a_pipe_gets_a_heartbeat_line_with_the_current_step(capsys):
    with ProgressBar(None, "optimize", heartbeat_s=0.05) as bar:  # stdout is no terminal here
        bar.step("RF: free-trajectory bound, 64 spans")
        time.sleep(0.3)
    lines = capsys.readouterr().err.splitlines()
    assert len(lines) >= 2
    assert all(
        line.startswith("scalf-opt: optimize: RF: free-trajectory bound, 64 spans (")
        for line in lines
    )


def test_short_work_and_quiet_runs_print_nothing(capsys):
    with ProgressBar(None, "optimize", heartbeat_s=5.0) as bar:
        bar.step("RF at 300 Hz")
    with ProgressBar(None, "optimize", enabled=False, heartbeat_s=0.01) as bar:
        bar.step("RF at 300 Hz")
        time.sleep(0.1)
    assert capsys.readouterr().err == ""


def test_the_heartbeat_stops_with_its_work(capsys):
    with Heartbeat("study", every_s=0.02) as beat:
        beat.doing = "3/10 cases done"
        time.sleep(0.1)
    capsys.readouterr()
    time.sleep(0.1)
    assert capsys.readouterr().err == ""


def test_a_compilation_inside_a_step_is_named_beside_it(capsys, tmp_path, monkeypatch):
    """A new robot's first solve compiles its kernels: the heartbeat says so beside the step,
    then the step alone again; a compilation nobody watches announces nothing."""
    import casadi as ca

    from scalf_opt.energy import codegen
    from scalf_opt.heartbeat import meanwhile

    if codegen._compiler() is None:  # pragma: no cover - a machine without a C compiler
        return
    monkeypatch.setenv("SCALF_OPT_CACHE", str(tmp_path / "cache"))
    x = ca.SX.sym("x")
    with meanwhile("nobody listens"):
        pass  # no listener: nothing to show, nothing raised
    slow = codegen._run_compiler

    def compiling_slowly(*args, **kwargs):
        time.sleep(0.3)
        return slow(*args, **kwargs)

    monkeypatch.setattr(codegen, "_run_compiler", compiling_slowly)
    with ProgressBar(None, "optimize", heartbeat_s=0.05) as bar:
        bar.step("joint-6 at 300 Hz")
        assert codegen.compile_library("progress_probe", [ca.Function("probe", [x], [x * x])])
        during = capsys.readouterr().err.splitlines()
        time.sleep(0.2)
    after = capsys.readouterr().err.splitlines()
    compiling = (
        "scalf-opt: optimize: joint-6 at 300 Hz: compiling progress_probe (once per machine) ("
    )
    assert any(line.startswith(compiling) for line in during)
    assert after and all(
        line.startswith("scalf-opt: optimize: joint-6 at 300 Hz (") for line in after
    )
