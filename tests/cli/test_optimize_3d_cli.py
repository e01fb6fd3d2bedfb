"""``optimize --model 3d``'s refusals: one line naming the option, exit 2, before any solve."""

import pytest

from scalf_opt.cli import main


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--duty", "0.1"], "--duty 0.1: duty_cycle = 0.1 is outside [0.2, 0.8] for the 3-D trot"),
        (["--family", "joint-4"], "--family is an option of the sagittal model"),
        (["--free-stance"], "--free-stance is an option of the sagittal model"),
        (["--loads", "trunk"], "--loads is an option of the sagittal model"),
        (["--leg", "rf"], "--leg is an option of the sagittal model"),
        (["--method", "pattern"], "--method: --model 3d is solved by Ipopt only"),
        (["--friction", "-1"], "--friction -1 must be > 0"),
        (["--friction", "nan"], "--friction nan must be > 0"),
        (["--rate", "0"], "--rate 0 must be > 0 [Hz]"),
        (["--rate", "nan"], "--rate nan must be > 0 [Hz]"),
    ],
)
def test_a_bad_3d_option_is_one_line(capsys, argv, message):
    code = main(["optimize", "--model", "3d", "--robot", "go1", *argv])
    assert code == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1


def test_a_mistyped_model_is_named(capsys):
    with pytest.raises(SystemExit) as info:
        main(["optimize", "--model", "3-d"])
    assert info.value.code == 2
    assert "--model" in capsys.readouterr().err


def test_a_rate_too_low_for_the_sagittal_gait_is_the_3d_grid_s_to_take():
    """Four samples per phase is the sagittal gait's rule; the 3-D driver's first grid keeps three
    nodes per phase whatever the rate, so HyQ's 16 Hz (3.6 per stance) is taken as asked."""
    from scalf_opt.cli.app import build_parser
    from scalf_opt.cli.commands.optimize import margins_from
    from scalf_opt.cli.commands.optimize_3d import build_problem

    args = build_parser().parse_args(
        ["optimize", "--model", "3d", "--robot", "hyq", "--rate", "16"]
    )
    problem, rate, _ = build_problem(args, margins_from(args))
    assert rate == 16.0 and args.sample_rate_hz == 16.0
    assert problem.schedule.period_s * problem.schedule.duty_cycle * rate < 4


def test_the_sagittal_optimize_refuses_the_3d_friction(capsys, tmp_path):
    """``--friction`` shapes the 3-D model's contact cones only: the sagittal optimize, which
    has none, refuses it rather than ignore it (it used to)."""
    out = tmp_path / "out"
    code = main(["optimize", "--friction", "0.5", "--out", str(out)])
    assert code == 2
    err = capsys.readouterr().err
    assert "--friction is an option of --model 3d" in err and err.count("\n") == 1
    assert not out.exists()
