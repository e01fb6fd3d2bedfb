"""The referee ensemble: each member changes one setting; the verdict is their median and spread.

And the referee measures physics, not its own input: a model 20 % wrong is told so.
"""

import dataclasses
import json
import math

import numpy as np
import pinocchio as pin
import pytest

from scalf_opt.cli import main
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.gait import Gait
from scalf_opt.sim.control import servo_gains
from scalf_opt.sim.ensemble import ENSEMBLE, NOMINAL, MemberResult, Perturbation, ensemble_verdict
from scalf_opt.sim.experiment import run_trot
from scalf_opt.sim.plan import REFERENCE_SWINGS, TrotPlan
from scalf_opt.sim.settings import SimSettings
from scalf_opt.types import LEG_NAMES


@pytest.fixture(scope="module")
def robot(scalf):
    return scalf  # the session's SCalf (tests/conftest.py)


@pytest.fixture(scope="module")
def pipeline(robot):
    return EnergyPipeline(robot, Gait())


def test_each_member_changes_one_setting_of_the_nominal_referee(robot):
    nominal = SimSettings()
    derived, _ = nominal.for_leg_length(robot.leg_length_m)
    assert ENSEMBLE[0] is NOMINAL and NOMINAL.applied(nominal, derived) is nominal
    names = [p.name for p in ENSEMBLE]
    assert len(set(names)) == len(names) == 10
    for p in ENSEMBLE[1:]:
        member = p.applied(nominal, derived)
        changed = [f for f, v in member.to_dict().items() if v != nominal.to_dict()[f]]
        assert changed == [p.field]
    by_name = {p.name: p.applied(nominal, derived) for p in ENSEMBLE}
    assert by_name["foot radius x3"].foot_radius_m == pytest.approx(3 * derived.foot_radius_m)
    assert by_name["friction 0.6"].foot_friction == 0.6
    assert by_name["touch-down 5 ms early"].schedule_shift_s == -0.005


def test_servo_gains_x2_is_twice_the_stiffness(robot, pipeline):
    """The servo members scale the loop's frequency by sqrt(2) both ways: its stiffness K_p =
    I omega^2 (and so the 'gains') by 2 and 1/2, computed here through the servo itself."""
    plan = TrotPlan.build(pipeline, REFERENCE_SWINGS, 2000.0)
    nominal = SimSettings()
    derived, _ = nominal.for_leg_length(robot.leg_length_m)

    def kp(settings):
        full, _ = settings.for_leg_length(robot.leg_length_m)
        return servo_gains(robot, plan, full)["RF"].kp_nm_per_rad

    by_name = {p.name: p for p in ENSEMBLE}
    double = by_name["servo gains x2"].applied(nominal, derived)
    half = by_name["servo gains x0.5"].applied(nominal, derived)
    np.testing.assert_allclose(kp(double), 2 * kp(nominal), rtol=1e-12)
    np.testing.assert_allclose(kp(half), 0.5 * kp(nominal), rtol=1e-12)


def _member(name, diffs, saving=-20.0):
    return MemberResult(
        Perturbation(name),
        dict(zip(LEG_NAMES, diffs, strict=True)),
        {leg: 100.0 * (1 + d) for leg, d in zip(LEG_NAMES, diffs, strict=True)},
        float(np.mean(diffs)),
        saving,
        0.0,
    )


def _nominal_data():
    energy = {
        leg: {"simulated": 100.0, "model": 100.0, "relative_difference": 0.0} for leg in LEG_NAMES
    }
    return {
        "joint_energy_per_cycle_j": energy,
        "total_energy_per_cycle_j": {
            "simulated": 400.0,
            "model": 400.0,
            "relative_difference": 0.0,
        },
        "goals": {"joint_energy_relative_difference_at_most": 0.05, "joint_energy_met": True},
        "saving_vs_reference": {
            "model_percent": -20.0,
            "simulated_percent": -20.0,
            "same_sign_within_a_third_met": True,
        },
    }


def test_the_verdict_is_the_median_and_states_its_spread():
    members = [
        _member("a", [0.01, 0.02, 0.01, 0.02], -19.0),
        _member("b", [0.03, 0.00, 0.03, 0.00], -21.0),
        _member("c", [-0.01, 0.04, -0.01, 0.04], -22.0),
    ]
    data = ensemble_verdict(_nominal_data(), members, 0.05)
    rf = data["joint_energy_per_cycle_j"]["RF"]
    assert rf["relative_difference"] == 0.01 and rf["simulated"] == pytest.approx(101.0)
    assert rf["relative_difference_spread"] == pytest.approx(0.04, abs=1e-15)
    assert data["joint_energy_per_cycle_j"]["LH"]["relative_difference"] == 0.02
    assert data["goals"]["refereeable"] and data["goals"]["joint_energy_met"]
    saving = data["saving_vs_reference"]
    assert saving["simulated_percent"] == -21.0 and saving["simulated_percent_spread"] == 3.0
    assert [m["name"] for m in data["ensemble"]["members"]] == ["a", "b", "c"]


def test_a_spread_beyond_the_goal_is_not_refereeable_never_agreeing():
    """Every median agrees (+1 %), but one referee says +7 % (6 points off): the verdict
    depends on the referee's settings, so it is not a verdict."""
    members = [_member(str(i), [0.01] * 4) for i in range(4)] + [
        _member("x", [0.07, 0.0, 0.0, 0.0])
    ]
    data = ensemble_verdict(_nominal_data(), members, 0.05)
    assert data["joint_energy_per_cycle_j"]["RF"]["relative_difference"] == 0.01
    assert data["goals"]["refereeable"] is False and data["goals"]["joint_energy_met"] is False
    from scalf_opt.sim.report import energy_goal_line

    assert energy_goal_line(data).endswith(
        "NOT refereeable (the referees disagree by up to 6.00 points)"
    )


def test_simulate_runs_the_ensemble_by_default_and_not_with_ensemble_off(tmp_path, capsys):
    on, off = tmp_path / "on", tmp_path / "off"
    assert main(["simulate", "--cycles", "2", "--out", str(on), "-q"]) == 0
    assert main(["simulate", "--cycles", "2", "--ensemble", "off", "--out", str(off), "-q"]) == 0
    with_ensemble = json.loads((on / "simulation.json").read_text())
    alone = json.loads((off / "simulation.json").read_text())
    members = with_ensemble["ensemble"]["members"]
    assert [m["name"] for m in members] == [p.name for p in ENSEMBLE]
    for leg in LEG_NAMES:
        energy = with_ensemble["joint_energy_per_cycle_j"][leg]
        diffs = [m["relative_difference"][leg] for m in members]
        assert energy["relative_difference"] == float(np.median(diffs))
        assert energy["relative_difference_spread"] == max(diffs) - min(diffs)
        # the nominal member is the referee run alone
        assert (
            members[0]["relative_difference"][leg]
            == alone["joint_energy_per_cycle_j"][leg]["relative_difference"]
        )
        assert "relative_difference_spread" not in alone["joint_energy_per_cycle_j"][leg]
    assert "ensemble" not in alone and "refereeable" not in alone["goals"]
    assert with_ensemble["ensemble"]["diverged"] == [] and alone["diverged_at_s"] is None
    assert all(m["diverged_at_s"] is None for m in members)
    report = (on / "report.txt").read_text()
    assert "in the median of 10 referees, spread at most 5 points: met" in report
    assert "touch-down 5 ms late" in report


def _heavier(robot, factor):
    """The robot with every link's mass and inertia ``factor`` times its own (a wrong model)."""
    model = robot.model.copy()
    for i, inertia in enumerate(model.inertias):
        model.inertias[i] = pin.Inertia(
            factor * inertia.mass, inertia.lever.copy(), factor * inertia.inertia.copy()
        )
    return dataclasses.replace(robot, model=model)


def test_a_model_20_percent_wrong_is_told_so(robot):
    """The referee measures physics, not its own input. The plan and the model's prediction come
    from a model whose masses are all 20 % too large (its feed-forward torques, its energy: both
    about 20 % high); MuJoCo simulates the robot as it is. Were the referee to echo the plan, it
    would agree; it must find the joints spending about a sixth less than the model says, and
    the verdict must say NOT met (while the right model agrees)."""
    heavy = _heavier(robot, 1.2)
    assert pin.computeTotalMass(heavy.model) == pytest.approx(
        1.2 * pin.computeTotalMass(robot.model)
    )
    gait = Gait()
    wrong = run_trot(robot, EnergyPipeline(heavy, gait), REFERENCE_SWINGS, SimSettings(), 3).result
    right = run_trot(robot, EnergyPipeline(robot, gait), REFERENCE_SWINGS, SimSettings(), 3).result
    for leg in LEG_NAMES:
        good = right["joint_energy_per_cycle_j"][leg]
        bad = wrong["joint_energy_per_cycle_j"][leg]
        assert abs(good["relative_difference"]) < 0.02
        # physics: the joints of the real robot spend what the real robot needs
        assert bad["simulated"] == pytest.approx(good["simulated"], rel=0.03)
        assert bad["relative_difference"] < -0.10
    assert right["goals"]["joint_energy_met"] and not wrong["goals"]["joint_energy_met"]
    # and the servo's feedback, which cancels the wrong feed-forward, shows where it went
    share = [
        wrong["servo_work_per_cycle_j"][leg]["feedback_torque_rms_over_torque_rms"]
        for leg in LEG_NAMES
    ]
    assert min(share) > 3 * max(
        right["servo_work_per_cycle_j"][leg]["feedback_torque_rms_over_torque_rms"]
        for leg in LEG_NAMES
    )
    assert math.isfinite(wrong["trunk_height_fluctuation_m"])


def test_a_member_whose_robot_fell_makes_the_plan_not_refereeable():
    """Within the spread, but one referee's robot fell: its energy measured a robot on the
    ground, so the verdict names it instead of agreeing."""
    members = [_member(str(i), [0.01] * 4) for i in range(4)]
    members.append(dataclasses.replace(_member("foot radius x3", [0.02] * 4), fell_at_s=1.25))
    data = ensemble_verdict(_nominal_data(), members, 0.05)
    assert data["goals"]["refereeable"] is False and data["goals"]["joint_energy_met"] is False
    assert data["ensemble"]["fell"] == ["foot radius x3"]
    assert data["ensemble"]["members"][-1]["fell_at_s"] == 1.25
    from scalf_opt.sim.report import energy_goal_line, ensemble_lines

    assert energy_goal_line(data).endswith("NOT refereeable (the robot fell under: foot radius x3)")
    assert ensemble_lines(data)[-1].endswith("fell at 1.250 s")


def test_a_fall_is_the_first_time_the_trunk_leaves_its_plan_by_a_fall():
    from types import SimpleNamespace

    from scalf_opt.sim.metrics import FALL_HEIGHT_SHARE, FALL_PITCH_RAD, fell_at_s

    t = np.arange(6) * 0.1
    level = np.zeros(6)
    height = np.full(6, 0.5)
    record = SimpleNamespace(t_s=t, start_trunk_height_m=0.5, trunk=np.vstack([t, height, level]))
    assert fell_at_s(record, 0.5) is None
    sinking = height - np.array([0, 0, 0.99, 1.01, 2, 3]) * FALL_HEIGHT_SHARE * 0.5
    record.trunk = np.vstack([t, sinking, level])
    assert fell_at_s(record, 0.5) == pytest.approx(0.3)
    pitched = np.array([0, 0.5, 1.01, 0, 0, 0]) * FALL_PITCH_RAD
    record.trunk = np.vstack([t, height, pitched])
    assert fell_at_s(record, 0.5) == pytest.approx(0.2)


def test_an_early_touch_down_switches_the_leg_in_the_air(robot, pipeline):
    """The "touch-down 5 ms early" member changes what the controller does: the leg joins the
    stance loop before its foot lands (the feet land about half a millisecond after the planned
    touch-down, so a switch that waited for the contact would be the nominal referee again)."""
    from scalf_opt.sim.mujoco_model import build_sim_model
    from scalf_opt.sim.run import simulate

    settings, _ = SimSettings().for_leg_length(robot.leg_length_m)
    plan = TrotPlan.build(pipeline, REFERENCE_SWINGS, 1.0 / settings.value("timestep_s"))
    sim = build_sim_model(robot, settings)
    gains = servo_gains(robot, plan, settings)
    from scalf_opt.sim.control import trunk_gains

    runs = {
        shift: simulate(sim, plan, gains, 2, trunk_gains(settings), shift)
        for shift in (0.0, -0.005)
    }
    t = runs[0.0].t_s
    # the 5 ms before RF's second planned touch-down (t = T): its foot is in the air in both
    window = (t > 0.5 - 0.005) & (t < 0.5 - 0.001)
    assert not runs[0.0].in_contact("RF")[window].any()
    assert not runs[-0.005].in_contact("RF")[window].any()
    # and its torques differ there: the stance loop's, not the swing loop's
    nominal, early = runs[0.0].tau_nm["RF"][:, window], runs[-0.005].tau_nm["RF"][:, window]
    assert np.abs(early - nominal).max() > 0.05 * np.abs(nominal).max()
    # until 5 ms before the first touch-down after the start (LF and RH at T / 2) the two
    # runs are the same to the last bit
    before = t < 0.25 - 0.005 - 1e-9
    np.testing.assert_array_equal(
        runs[0.0].tau_nm["RF"][:, before], runs[-0.005].tau_nm["RF"][:, before]
    )
