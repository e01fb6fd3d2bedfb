"""``figures --from DIR`` on a 3-D cycle: the trunk figure, drawn from the files alone."""

import json

import numpy as np
import pytest

from scalf_opt.cli import main
from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.io.whole_body_export import read_cycle, write_cycle
from scalf_opt.locomotion.contact_schedule import trot_schedule
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.optimize.whole_body_start import starting_plan
from scalf_opt.robots.loading import load_robot
from scalf_opt.viz.whole_body_figure import roll_pitch_rad


@pytest.fixture(scope="module")
def cycle_dir(tmp_path_factory):
    """A flying trot's kinematic start written as ``optimize --model 3d --out`` writes a cycle."""
    robot = load_robot("go1")
    gait = default_gait_for(robot)
    physics = WholeBodyPhysics.of(robot)
    schedule = trot_schedule(gait.period_s, 0.4, 100.0)
    plan = starting_plan(physics, schedule, 0.5, gait.stance_height_m, gait.clearance_m)
    summary = {
        "model": "3d",
        "robot": robot.name,
        "period_s": schedule.period_s,
        "duty_cycle": schedule.duty_cycle,
        "speed_m_s": 0.5,
        "energy_per_cycle_j": plan.evaluate("paper").total_j,
        "cost_of_transport": 0.5,
    }
    out = tmp_path_factory.mktemp("cycle")
    write_cycle(out, summary, plan, "paper")
    return out, plan


def test_roll_and_pitch_come_back_from_the_quaternion():
    rng = np.random.default_rng(3)
    roll, pitch, yaw = rng.uniform(-0.5, 0.5, (3, 20))
    # the quaternion of R_z(yaw) R_y(pitch) R_x(roll), written out independently
    cr, sr = np.cos(roll / 2), np.sin(roll / 2)
    cp, sp = np.cos(pitch / 2), np.sin(pitch / 2)
    cy, sy = np.cos(yaw / 2), np.sin(yaw / 2)
    quat = np.vstack(
        [
            sr * cp * cy - cr * sp * sy,
            cr * sp * cy + sr * cp * sy,
            cr * cp * sy - sr * sp * cy,
            cr * cp * cy + sr * sp * sy,
        ]
    )
    got_roll, got_pitch = roll_pitch_rad(quat)
    np.testing.assert_allclose(got_roll, roll, atol=1e-12)
    np.testing.assert_allclose(got_pitch, pitch, atol=1e-12)


def test_a_saved_cycle_reads_back_as_written(cycle_dir):
    out, plan = cycle_dir
    cycle = read_cycle(out)
    assert cycle.feet == plan.physics.feet
    np.testing.assert_array_equal(cycle.columns["base_pos_z_m"], plan.x[2])
    fz = np.vstack([cycle.columns[f"{foot}_force_z_n"] for foot in cycle.feet])
    np.testing.assert_array_equal(fz, plan.forces_n[2::3])


def test_figures_draws_the_trunk_of_a_3d_cycle(cycle_dir, tmp_path, capsys):
    out, _ = cycle_dir
    code = main(["figures", "--from", str(out), "--out", str(tmp_path), "--format", "png"])
    assert code == 0
    assert (tmp_path / "trunk.png").stat().st_size > 10_000
    assert "wrote" in capsys.readouterr().out


def test_a_3d_cycle_is_not_drawn_with_a_sagittal_result(cycle_dir, tmp_path, capsys):
    out, _ = cycle_dir
    sagittal = tmp_path / "sagittal"
    sagittal.mkdir()
    code = main(["figures", "--from", str(out), "--from", str(sagittal), "--out", str(tmp_path)])
    assert code == 2
    err = capsys.readouterr().err
    assert f"--from {sagittal}: not a 3-D cycle" in err and err.count("\n") == 1


def test_a_broken_plan_csv_is_named(cycle_dir, tmp_path, capsys):
    out, _ = cycle_dir
    broken = tmp_path / "broken"
    broken.mkdir()
    (broken / "summary.json").write_text(json.dumps({"model": "3d"}))
    text = (out / "plan.csv").read_text().replace("base_pos_z_m", "base_pos_zz")
    (broken / "plan.csv").write_text(text)
    code = main(["figures", "--from", str(broken), "--out", str(tmp_path / "f")])
    assert code == 2
    err = capsys.readouterr().err
    assert "plan.csv: no column 'base_pos_z_m'" in err and err.count("\n") == 1
    assert not (tmp_path / "f").exists()
