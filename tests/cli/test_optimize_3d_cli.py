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
