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
        (["--cycles", "1"], "cycles must be an integer in 2..200"),
        (["--robot", "a1"], "summary.json: the cycle of robot 'go1', not of 'a1'"),
    ],
)
def test_a_bad_option_is_one_line(capsys, tmp_path, cycle_dir, argv, message):
    code = main(["simulate", "--from", str(cycle_dir), "--out", str(tmp_path / "o"), *argv])
    err = capsys.readouterr().err
    assert code == 2, err
    assert message in err and err.count("\n") == 1
    assert not (tmp_path / "o").exists()


def test_a_cycle_without_its_plan_is_named(capsys, tmp_path, cycle_dir):
    broken = tmp_path / "broken"
    shutil.copytree(cycle_dir, broken)
    (broken / "plan.csv").unlink()
    code = main(["simulate", "--from", str(broken), "--out", str(tmp_path / "o")])
    err = capsys.readouterr().err
    assert code == 2 and "plan.csv: cannot be read" in err and err.count("\n") == 1
    assert json.loads((broken / "summary.json").read_text())["model"] == "3d"
