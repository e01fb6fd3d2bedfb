"""``evaluate --model 3d``'s refusals: one line naming the option, exit 2, before any solve."""

import pytest

from scalf_opt.cli import main


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--model", "3d", "--swing", "results/x"], "--swing: --model 3d evaluates the reference"),
        (["--model", "3d", "--loads", "trunk"], "--loads is an option of the sagittal model"),
        (["--model", "3d", "--duty", "0.1"], "duty_cycle = 0.1 is outside [0.2, 0.8]"),
        (["--model", "3d", "--friction", "0"], "--friction 0 must be > 0"),
        (["--model", "3d", "--rate", "-5"], "--rate -5 must be > 0 [Hz]"),
        (["--friction", "0.5"], "--friction is an option of --model 3d"),
        (["--accept-unconverged"], "--accept-unconverged is an option of --model 3d"),
        (["--model", "3d", "--friction", "inf"], "--friction inf must be > 0"),
    ],
)
def test_a_bad_3d_option_is_one_line(capsys, tmp_path, argv, message):
    out = tmp_path / "out"
    code = main(["evaluate", "--robot", "go1", "--out", str(out), *argv])
    assert code == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert not out.exists()


def test_an_unconverged_balance_writes_only_when_accepted(capsys, tmp_path, monkeypatch):
    """Ipopt replaced by a stand-in that stops at the kinematic start, unconverged: exit 3 and
    nothing written; with ``--accept-unconverged`` exit 0, written and marked not converged."""
    import json

    from scalf_opt.optimize import whole_body_driver
    from scalf_opt.optimize.whole_body_driver import CycleResult, GridStep
    from scalf_opt.optimize.whole_body_nlp import CycleSolution, kinematic_start

    def stand_in(problem, rate, progress=None, start=None):
        plan = kinematic_start(problem)
        solution = CycleSolution(plan, plan, False, "Maximum_Iterations_Exceeded", 3000, 1.0)
        energy = plan.evaluate(problem.accounting).total_j
        step = GridStep(
            problem.schedule.intervals,
            problem.schedule.reads_per_interval,
            solution,
            energy,
            plan.check(problem.accounting),
        )
        return CycleResult((step,))

    monkeypatch.setattr(whole_body_driver, "optimize_cycle", stand_in)
    out = tmp_path / "ref"
    argv = ["evaluate", "--model", "3d", "--robot", "go1", "--rate", "25", "--out", str(out)]
    assert main(argv) == 3
    assert "not converged: Ipopt on 10 nodes: Maximum_Iterations_Exceeded" in (
        capsys.readouterr().err
    )
    assert not out.exists()
    assert main([*argv, "--accept-unconverged"]) == 0
    summary = json.loads((out / "summary.json").read_text())
    assert summary["objective"] == "reference" and summary["converged"] is False
    assert "Maximum_Iterations_Exceeded" in summary["failure"]
    assert (out / "plan.csv").exists()
