"""``gait --model 3d``: its refusals (one line naming the option, exit 2, before any solve), and
its table, files and exit code around the per-speed solves."""

import csv
import json

import pytest

from scalf_opt.api import gait_3d
from scalf_opt.api.gait_3d import StartAnswer, speed_row
from scalf_opt.cli import main


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--model", "3d", "--family", "joint-4"], "--family is an option of the sagittal gait"),
        (["--model", "3d", "--loads", "trunk"], "--loads is an option of the sagittal gait"),
        (["--model", "3d", "--method", "pattern"], "--method is an option of the sagittal gait"),
        (["--model", "3d", "--duty", "0.1"], "--duty 0.1: duty_cycle = 0.1 is outside [0.2, 0.8]"),
        (["--model", "3d", "--duty", "0.5,x"], "--duty 0.5,x: give numbers separated by commas"),
        (["--model", "3d", "--period", "-1"], "--period -1: every value must be a number > 0"),
        (["--model", "3d", "--period", "5"], "--period 5: outside --period-range"),
        (["--model", "3d", "--period-range", "0.5:0.2"], "--period-range 0.5:0.2: needs 0 < MIN"),
        (["--model", "3d", "--period-range", "abc"], "--period-range abc: give MIN:MAX"),
        (["--model", "3d", "--rate", "0"], "--rate 0 must be in (0, 1000] [Hz]"),
        (["--model", "3d", "--sagittal", "/nonexistent/x"], "--sagittal /nonexistent/x"),
        (["--duty", "0.5"], "--duty is an option of --model 3d"),
        (["--period-range", "0.2:0.5"], "--period-range is an option of --model 3d"),
        (["--sagittal", "x.csv"], "--sagittal is an option of --model 3d"),
        (["--friction", "0.5"], "--friction is an option of --model 3d"),
        (["--model", "3d", "--friction", "0"], "--friction 0 must be > 0"),
        (["--model", "3d", "--friction", "nan"], "--friction nan must be > 0"),
    ],
)
def test_a_bad_option_is_one_line(capsys, tmp_path, argv, message):
    code = main(["gait", "--robot", "go1", "--speed", "0.5", "--out", str(tmp_path / "o"), *argv])
    assert code == 2
    err = capsys.readouterr().err
    assert message in err and err.count("\n") == 1
    assert not (tmp_path / "o").exists()


def _answer(duty, period, converged, cot, failure=""):
    summary = {
        "period_s": period * 0.9,
        "duty_cycle": duty,
        "stride_m": 0.5 * period * 0.9,
        "energy_per_cycle_j": cot * 100 * 0.5 * period * 0.9,
        "cost_of_transport": cot,
        "rate_difference": 0.001,
        "grid_change": -0.05,
        "grid_change_from_nodes": 10,
        "nodes": 20,
        "pinned_by": ["RF_knee q upper: joint range (URDF), less margin"],
        "solves": [{"seconds": 3.0}],
    }
    return StartAnswer(duty, period, converged, failure, summary, "t_s\n0.0\n")


def test_a_speed_keeps_its_cheapest_converged_start():
    answers = [
        _answer(0.5, 0.4, True, 0.30),
        _answer(0.35, 0.3, False, 0.10, "Ipopt on 8 nodes: Maximum_Iterations_Exceeded"),
        _answer(0.6, 0.5, True, 0.25),
    ]
    row = speed_row("go1", 0.5, answers)
    assert row["status"] == "ok" and row["starts_converged"] == 2
    assert row["cost_of_transport"] == 0.25 and row["start_duty_cycle"] == 0.6
    assert row["step_length_m"] == pytest.approx(0.5 * 0.6 * 0.45)
    assert row["solve_s"] == 9.0
    failed = speed_row("go1", 0.5, [answers[1]])
    assert failed["status"] == "not converged"
    assert "duty 0.35, T 0.3 s: Ipopt on 8 nodes" in failed["error"]


def test_the_sweep_writes_its_table_and_exits_3_when_a_speed_fails(capsys, tmp_path, monkeypatch):
    """The solves replaced by fixed answers (the real ones are the NLP's tests): the command
    writes gaits.csv, gaits.png and the solved speed's files, prints the table and what pins
    the answer, and exits 3 for the speed no start converged at."""

    seen = []

    def fake(case, physics, previous):
        assert case.friction == 0.6  # --friction reaches every speed's NLP
        seen.append((case.speed_m_s, dict(previous)))
        if case.speed_m_s > 1:
            failed = _answer(0.5, 0.4, False, 0.2, "Ipopt on 8 nodes: Infeasible_Problem_Detected")
            return [failed], {}
        return [_answer(0.5, 0.4, True, 0.3), _answer(0.4, 0.4, True, 0.28)], {(0.5, 0.4): "plan"}

    monkeypatch.setattr(gait_3d, "_solve_speed", fake)
    out = tmp_path / "sweep"
    argv = ["gait", "--model", "3d", "--robot", "go1", "--speed", "0.5,1.5"]
    code = main(
        [*argv, "--duty", "0.5,0.4", "--friction", "0.6", "--workers", "1", "--out", str(out)]
    )
    captured = capsys.readouterr()
    assert code == 3
    assert "1 of 2 speeds did not converge" in captured.err
    assert "0.5 m/s pinned at: q upper of RF_knee (joint range (URDF), less margin)" in (
        captured.out
    )
    rows = list(csv.DictReader((out / "gaits.csv").open()))
    assert [r["status"] for r in rows] == ["ok", "not converged"]
    assert float(rows[0]["grid_change"]) == -0.05 and rows[1]["grid_change"] == ""
    table = captured.out.splitlines()
    assert table[1].split()[-4:] == ["10x", "grid", "starts", "status"]
    assert "-5.00 %" in table[2]
    assert float(rows[0]["cost_of_transport"]) == 0.28
    assert (out / "gaits.png").stat().st_size > 10_000
    summary = json.loads((out / "speed_0.5" / "summary.json").read_text())
    assert [s["cost_of_transport"] for s in summary["starts"]] == [0.3, 0.28]
    assert (out / "speed_0.5" / "plan.csv").read_text() == "t_s\n0.0\n"
    assert not (out / "speed_1.5").exists()
    # one chain (slowest first): the second speed starts from the first's converged plans
    assert seen == [(0.5, {}), (1.5, {(0.5, 0.4): "plan"})]
