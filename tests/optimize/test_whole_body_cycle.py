"""An optimized 3-D cycle against Pinocchio: dynamics, contacts, periodicity, flight.

The plan is solved on a coarse grid (the driver's first step) to keep the test short; every
property below is a constraint of the NLP, so it holds on any grid. Pinocchio's free-flyer model
is rebuilt from the URDF here, independently of the model the NLP's CasADi twin was built from.
"""

import numpy as np
import pinocchio as pin
import pytest

from scalf_opt.locomotion.periodic_spline import continuity_rows
from tests.optimize.whole_body_checks import (
    assert_contacts_hold,
    assert_pinocchio_agrees,
    free_flyer_model,
)

pytestmark = [pytest.mark.slow, pytest.mark.xdist_group(name="whole_body_cycle")]


@pytest.fixture(scope="module")
def solved(go1_cycle):
    return go1_cycle


def test_the_optimum_converges_and_saves_on_its_start(solved):
    _, solution = solved
    assert solution.success, solution.status
    start = solution.start.evaluate("paper").total_j
    assert solution.plan.evaluate("paper").total_j < 0.5 * start


def test_pinocchio_gives_the_plans_torques_and_no_trunk_wrench_at_every_node(solved):
    problem, solution = solved
    assert_pinocchio_agrees(problem, solution.plan)


def test_contact_forces_push_inside_their_cones_and_vanish_in_swing(solved):
    problem, solution = solved
    assert_contacts_hold(problem, solution.plan)


def test_the_cycle_closes_on_itself_one_stride_ahead(solved):
    problem, solution = solved
    plan = solution.plan
    values, rates = continuity_rows(plan.x, plan.xd, plan.xdd, problem.schedule.step_s, plan.shift)
    assert np.abs(values).max() < 1e-8 and np.abs(rates).max() * problem.schedule.step_s < 1e-8
    # the stance feet stand on the flat ground at their footholds
    feet = plan.node_outputs("paper")["feet_pos"].reshape(3, -1, 4)
    for i in range(4):
        on = problem.schedule.stance[i]
        np.testing.assert_allclose(feet[2, on, i], 0.0, atol=1e-8)


def test_the_export_is_the_plan_a_controller_can_recheck(solved, tmp_path):
    import csv
    import json

    from scalf_opt.cli.commands.optimize_3d import cycle_report, cycle_summary
    from scalf_opt.io.whole_body_export import write_cycle
    from scalf_opt.optimize.whole_body_driver import CycleResult, GridStep

    problem, solution = solved
    plan = solution.plan
    step = GridStep(
        problem.schedule.intervals,
        problem.schedule.reads_per_interval,
        solution,
        plan.evaluate("paper").total_j,
        plan.check("paper"),
    )
    result = CycleResult((step,))
    summary = cycle_summary(problem, result)
    written = write_cycle(tmp_path, summary, plan, "paper")
    assert [p.name for p in written] == ["plan.csv", "summary.json"]
    assert json.loads((tmp_path / "summary.json").read_text())["model"] == "3d"
    rows = list(csv.DictReader((tmp_path / "plan.csv").open()))
    assert len(rows) == problem.schedule.intervals
    columns = rows[0].keys()
    for stem in ("base_pos_{}_m", "base_lin_vel_{}_m_s", "base_ang_acc_{}_rad_s2"):
        assert all(stem.format(a) in columns for a in "xyz")
    for joint in problem.physics.joint_names:
        assert {f"{joint}_q_rad", f"{joint}_tau_nm"} <= columns
    table = {c: np.array([float(r[c]) for r in rows]) for c in columns}
    quat = np.vstack([table[f"base_quat_{a}"] for a in "xyzw"])
    np.testing.assert_allclose(np.linalg.norm(quat, axis=0), 1.0, atol=1e-14)
    np.testing.assert_array_equal(table["base_lin_acc_z_m_s2"], plan.xdd[2])
    foot = problem.physics.feet[0]
    swing = ~problem.schedule.stance[0]
    assert (table[f"{foot}_force_z_n"][swing] == 0).all()
    # the world angular velocity is the trunk's rpy rates mapped: its z is the yaw rate when
    # roll and pitch are small (here within a degree), to their second order
    np.testing.assert_allclose(table["base_ang_vel_z_rad_s"], plan.xd[5], atol=1e-2)
    report = cycle_report(problem, summary)
    assert "cost of transport" in report and "Solve_Succeeded" in report
    # the pinned limits are always reported: named, or none
    pinned = [line for line in report.splitlines() if line.startswith("pinned at")]
    assert len(pinned) == 1
    assert ("no limit" in pinned[0]) == (not summary["pinned_by"]), pinned
    unpinned = cycle_report(problem, {**summary, "pinned_by": []})
    assert "pinned at                no limit:" in unpinned


def test_where_no_foot_carries_the_exported_robot_falls_at_g(solved, tmp_path):
    """At the pair switch no foot carries force (duty 0.5; in a flying trot the whole flight):
    read from plan.csv alone into Pinocchio's own model, the centre of mass accelerates at g."""
    import csv
    from functools import partial

    from scalf_opt.io.whole_body_export import plan_csv

    problem, solution = solved
    physics = problem.physics
    (tmp_path / "plan.csv").write_text(plan_csv(solution.plan, "paper"))
    rows = list(csv.DictReader((tmp_path / "plan.csv").open()))
    model = free_flyer_model(physics)
    data = model.createData()
    joints = [model.names[j] for j in range(2, model.njoints)]
    falling = 0
    for row in rows:
        get = partial(_values, row)
        forces = get(*(f"{f}_force_{a}_n" for f in physics.feet for a in "xyz"))
        if np.any(forces != 0):
            continue
        falling += 1
        quat = get(*(f"base_quat_{a}" for a in "xyzw"))
        rot = pin.Quaternion(quat[3], *quat[:3]).toRotationMatrix()
        lin_vel = get(*(f"base_lin_vel_{a}_m_s" for a in "xyz"))
        ang_vel = get(*(f"base_ang_vel_{a}_rad_s" for a in "xyz"))
        lin_acc = get(*(f"base_lin_acc_{a}_m_s2" for a in "xyz"))
        ang_acc = get(*(f"base_ang_acc_{a}_rad_s2" for a in "xyz"))
        body_vel, body_ang = rot.T @ lin_vel, rot.T @ ang_vel
        q = np.concatenate(
            [get(*(f"base_pos_{a}_m" for a in "xyz")), quat, get(*(f"{j}_q_rad" for j in joints))]
        )
        v = np.concatenate([body_vel, body_ang, get(*(f"{j}_v_rad_s" for j in joints))])
        # Pinocchio's free-flyer acceleration: the body-frame velocity's time derivative
        a = np.concatenate(
            [
                rot.T @ lin_acc - np.cross(body_ang, body_vel),
                rot.T @ ang_acc,
                get(*(f"{j}_a_rad_s2" for j in joints)),
            ]
        )
        pin.centerOfMass(model, data, q, v, a)
        # the trunk's force rows hold to Ipopt's 1e-8 of the weight: ~1e-7 m/s^2 here
        np.testing.assert_allclose(data.acom[0], model.gravity.linear, rtol=0, atol=1e-6)
    assert falling == 2  # the two pair switches of a duty-0.5 trot


def _values(row, *names):
    return np.array([float(row[n]) for n in names])


def test_a_free_period_moves_and_costs_less_per_metre(solved):
    """The period a decision variable (started from the fixed-period optimum, a feasible point
    of the free problem): the answer's period leaves the start, stays in its range, costs less
    per metre (the objective is the mean power at a fixed speed), and is still a plan Pinocchio
    agrees with, closing one stride ``v T`` ahead at its own period."""
    from dataclasses import replace

    from scalf_opt.optimize.whole_body_nlp import solve_cycle

    problem, fixed = solved
    period = problem.schedule.period_s
    free = replace(problem, period_range_s=(0.5 * period, 2.0 * period))
    solution = solve_cycle(free, fixed.plan)
    assert solution.success, solution.status
    plan = solution.plan
    assert 0.5 * period <= plan.schedule.period_s <= 2.0 * period
    assert abs(plan.schedule.period_s / period - 1) > 0.01
    cot = plan.cost_of_transport(plan.evaluate("paper").total_j)
    fixed_cot = fixed.plan.cost_of_transport(fixed.plan.evaluate("paper").total_j)
    assert cot < fixed_cot
    moved = replace(free, schedule=plan.schedule)
    assert_pinocchio_agrees(moved, plan)
    assert_contacts_hold(moved, plan)
    step = plan.schedule.step_s
    values, rates = continuity_rows(plan.x, plan.xd, plan.xdd, step, plan.shift)
    assert np.abs(values).max() < 1e-8 and np.abs(rates).max() * step < 1e-8
    assert plan.stride_m == pytest.approx(problem.speed_m_s * plan.schedule.period_s, rel=1e-12)


def test_another_speed_starts_from_this_plan_on_its_grid(solved, monkeypatch):
    """What ``gait --model 3d``'s chains do: the next speed's solve starts from this speed's
    optimum on the optimum's own grid (not the coarse one), needs fewer iterations than this
    cold solve did, and is a plan Pinocchio agrees with at the new speed (the ten-times rule's
    extra doublings switched off: one solve)."""
    from dataclasses import replace

    from scalf_opt.optimize import whole_body_driver
    from scalf_opt.optimize.whole_body_driver import optimize_cycle

    problem, cold = solved
    monkeypatch.setattr(whole_body_driver, "MAX_EXTRA_REFINEMENTS", 0)
    faster = replace(problem, speed_m_s=problem.speed_m_s + 0.1)
    rate = problem.schedule.intervals / problem.schedule.period_s
    result = optimize_cycle(faster, rate, start=cold.plan)
    assert [step.nodes for step in result.steps] == [problem.schedule.intervals]
    solution = result.last.solution
    assert solution.success, solution.status
    assert solution.iterations < cold.iterations
    plan = solution.plan
    assert plan.speed_m_s == faster.speed_m_s
    assert plan.stride_m == pytest.approx(faster.speed_m_s * plan.schedule.period_s, rel=1e-12)
    assert_pinocchio_agrees(faster, plan)
    assert_contacts_hold(faster, plan)


def test_the_balanced_reference_keeps_to_the_reference_and_costs_more_than_the_optimum(solved):
    """``evaluate --model 3d``'s problem (objective ``"reference"``) on the fixture's grid: a plan
    Pinocchio agrees with, in its cones, that keeps to the kinematic reference trot far closer
    than the energy optimum does and costs more than it (each objective does what it says)."""
    from dataclasses import replace

    from scalf_opt.optimize.whole_body_nlp import kinematic_start, solve_cycle

    problem, optimum = solved
    balanced_problem = replace(problem, objective="reference")
    solution = solve_cycle(balanced_problem)
    assert solution.success, solution.status
    plan = solution.plan
    assert_pinocchio_agrees(balanced_problem, plan)
    assert_contacts_hold(balanced_problem, plan)
    reference = kinematic_start(problem).x
    scale = np.ones((reference.shape[0], 1))
    scale[:3] = problem.stance_height_m

    def deviation(x):
        return float(np.mean(np.sum(((x - reference) / scale) ** 2, axis=0)))

    assert deviation(plan.x) < 0.1 * deviation(optimum.plan.x)
    energy = plan.evaluate("paper").total_j
    assert energy > 1.5 * optimum.plan.evaluate("paper").total_j
