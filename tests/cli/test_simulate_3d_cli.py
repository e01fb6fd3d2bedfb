"""``simulate --from DIR`` of a 3-D cycle: its refusals, one line each, before any simulation.

The cycle is Go1's kinematic start written as ``optimize --model 3d --out`` writes a cycle (no
solve: the refusals come before the referee runs).
"""

import json
import shutil

import pytest

from scalf_opt.cli import main
from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.io.whole_body_export import write_cycle
from scalf_opt.locomotion.contact_schedule import trot_schedule
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.optimize.whole_body_nlp import CycleProblem, kinematic_start
from scalf_opt.robots.loading import load_robot


@pytest.fixture(scope="module")
def cycle_dir(tmp_path_factory):
    physics = WholeBodyPhysics.of(load_robot("go1"))
    gait = default_gait_for(physics.robot)
    schedule = trot_schedule(gait.period_s, 0.5, 25.0)
    problem = CycleProblem(
        physics, schedule, gait.speed_m_s, gait.stance_height_m, gait.clearance_m
    )
    summary = {
        "model": "3d",
        "robot": "go1",
        "period_s": schedule.period_s,
        "duty_cycle": 0.5,
        "speed_m_s": gait.speed_m_s,
        "nodes": schedule.intervals,
        "friction": 0.8,
        "accounting": "paper",
    }
    out = tmp_path_factory.mktemp("cycle")
    write_cycle(out, summary, kinematic_start(problem), "paper")
    return out


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--log", "x.csv"], "--log: a 3-D cycle's simulation writes no sensor log"),
        (["--loads", "trunk"], "--loads: a 3-D cycle carries its own contact forces"),
        (["--period", "0.4"], "--gait and the gait options: with --from DIR the gait is DIR's"),
        (["--cycles", "1"], "--cycles: cycles must be an integer in 2..200"),
        (["--robot", "a1"], "summary.json: the cycle of robot 'go1', not of 'a1'"),
    ],
)
def test_a_bad_option_is_one_line(capsys, tmp_path, cycle_dir, argv, message):
    code = main(["simulate", "--from", str(cycle_dir), "--out", str(tmp_path / "o"), *argv])
    err = capsys.readouterr().err
    assert code == 2, err
    assert message in err and err.count("\n") == 1
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("cycles", ["1", "0"])
def test_too_few_cycles_to_measure_are_one_line(capsys, tmp_path, cycles):
    """The first cycle is the start-up, not measured: one cycle would measure nothing (a NaN
    verdict), so ``--cycles 1`` is refused before the referee runs, as with ``--from DIR``."""
    out = tmp_path / "o"
    code = main(
        ["simulate", "--model", "3d", "--robot", "go1", "--cycles", cycles, "--out", str(out)]
    )
    err = capsys.readouterr().err
    assert code == 2, err
    assert err.startswith("scalf-opt: error: --cycles: cycles must be an integer in 2..200")
    assert err.count("\n") == 1 and not out.exists()


def test_two_cycles_measure_one(capsys, tmp_path):
    """Go1's trot lasts 705.5 steps: two cycles are a hair more than 1,411 steps, and the run
    once stopped a step short of them, measured no cycle and printed a NaN verdict."""
    out = tmp_path / "sim"
    argv = ["simulate", "--model", "3d", "--robot", "go1", "--cycles", "2", "--ensemble", "off"]
    code = main([*argv, "--out", str(out)])
    text = capsys.readouterr().out
    assert code == 0
    assert "(each cycle after the first, 1 measured)" in text and "nan" not in text.lower()
    data = json.loads((out / "simulation.json").read_text())
    assert data["cycles"] == 2 and data["cycles_measured"] == 1


def test_a_cycle_without_its_plan_is_named(capsys, tmp_path, cycle_dir):
    broken = tmp_path / "broken"
    shutil.copytree(cycle_dir, broken)
    (broken / "plan.csv").unlink()
    code = main(["simulate", "--from", str(broken), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2 and "plan.csv: plan file not found" in err and err.count("\n") == 1
    assert json.loads((broken / "summary.json").read_text())["model"] == "3d"


def test_a_sagittal_plan_in_the_3d_referee(capsys, tmp_path):
    """SCalf's reference trot with the whole robot free: it holds (measured: -0.6 to -0.3 % per
    leg), and the report names both models' energies."""
    out = tmp_path / "sim"
    code = main(
        ["simulate", "--model", "3d", "--ensemble", "off", "--cycles", "2", "--out", str(out)]
    )
    text = capsys.readouterr().out
    assert code == 0
    assert "3-D referee of scalf's sagittal plan" in text
    assert "the sagittal model's own energy per cycle" in text
    assert "goal: joint energy within 5 % of the model's on every leg: met" in text
    data = json.loads((out / "simulation.json").read_text())
    assert data["model"] == "3d" and data["plan"] == "sagittal"
    assert {p.name for p in out.iterdir()} == {"simulation.json", "simulation.png", "report.txt"}


def test_a_3d_cycle_is_not_refereed_by_the_sagittal_referee(capsys, tmp_path, cycle_dir):
    code = main(
        ["simulate", "--model", "sagittal", "--from", str(cycle_dir), "--out", str(tmp_path / "o")]
    )
    err = capsys.readouterr().err
    assert code == 2 and "--model sagittal:" in err and "holds a 3-D cycle" in err


def test_a_cell_that_is_not_a_number_is_named_by_row_and_column(capsys, tmp_path, cycle_dir):
    broken = tmp_path / "broken"
    shutil.copytree(cycle_dir, broken)
    lines = (broken / "plan.csv").read_text().splitlines()
    cells = lines[2].split(",")
    cells[0] = "oops"
    lines[2] = ",".join(cells)
    (broken / "plan.csv").write_text("\n".join(lines) + "\n")
    code = main(["simulate", "--from", str(broken), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert "plan.csv: row 3, column 't_s': 'oops' is not a number" in err
