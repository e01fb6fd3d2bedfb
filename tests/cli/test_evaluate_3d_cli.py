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
    ],
)
def test_a_bad_3d_option_is_one_line(capsys, tmp_path, argv, message):
    out = tmp_path / "out"
    code = main(["evaluate", "--robot", "go1", "--out", str(out), *argv])
    assert code == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert not out.exists()
