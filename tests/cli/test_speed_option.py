"""``--speed`` on evaluate and optimize: the step length follows from the gait's duty and
period (``S = v d T``), instead of ``--step-length``."""

import json

import pytest

from scalf_opt.cli import main


@pytest.mark.parametrize(
    ("argv", "period", "duty"),
    [
        ([], 0.5, 0.5),
        (["--period", "0.6", "--duty", "0.6"], 0.6, 0.6),
        (["--robot", "go1", "--period", "0.4"], 0.4, 0.5),
    ],
)
def test_the_speed_sets_the_step_length(capsys, argv, period, duty):
    assert main(["evaluate", "--speed", "0.8", *argv, "--loads", "trunk", "--json"]) == 0
    gait = json.loads(capsys.readouterr().out)["gait"]
    assert gait["period_s"] == period and gait["duty_cycle"] == duty
    assert gait["step_length_m"] == pytest.approx(0.8 * duty * period, rel=1e-12)
    assert gait["speed_m_s"] == pytest.approx(0.8, rel=1e-12)


def test_an_optimum_walks_at_the_speed_and_says_so(capsys, tmp_path):
    argv = ["optimize", "--speed", "0.6", "--leg", "RF", "--family", "paper", "--loads", "trunk"]
    assert main([*argv, "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out
    assert "under --speed 0.6 (step length S = v d T)" in out.splitlines()[0]
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["gait"]["speed_m_s"] == pytest.approx(0.6, rel=1e-12)


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--speed", "0.8", "--step-length", "0.2"], "--step-length: not allowed with"),
        (["--speed", "0"], "--speed 0: the speed must be a number in (0, 10] m/s"),
        (["--speed", "nan"], "--speed nan: the speed must be a number"),
        (  # a speed within range whose step the legs cannot reach names the speed, not the gait
            ["--speed", "9"],
            "--speed 9 asks a step length S = v d T = 2.25 m, which the stance cannot walk: leg",
        ),
    ],
)
def test_a_bad_speed_is_one_line_naming_the_option(capsys, argv, message):
    try:
        code = main(["evaluate", *argv])
    except SystemExit as exc:  # argparse's own refusals
        code = exc.code
    assert code == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
