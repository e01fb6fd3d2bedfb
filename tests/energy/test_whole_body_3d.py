"""The 3-D whole-body model against Pinocchio: coordinates, loads, drives, and a plan's re-check.

The coordinates' map to Pinocchio's free-flyer state is checked by finite differences of
``pin.difference`` (the velocity) and of the velocity itself (the acceleration), not by the
formula that builds it. The loads (base wrench and joint torques with contact forces) are checked
against ``pin.rnea`` with the forces as external forces, at random states of every robot.
"""

import numpy as np
import pinocchio as pin
import pytest

from scalf_opt.actuators.electric import ElectricDrive
from scalf_opt.energy.whole_body import (
    DRIVE_FROM_FILE,
    DRIVE_FROM_HIP,
    DRIVE_IDEAL,
    WholeBodyPhysics,
)
from scalf_opt.robots.catalog import CATALOG
from scalf_opt.robots.loading import load_robot

FD_STEP_S = 1e-6
FD_TOL = 1e-7  # central differences of a smooth map at 1e-6: truncation ~1e-12, round-off ~1e-10
TOL = 1e-9  # exact maths, relative to max(1, |reference|)


@pytest.fixture(scope="module", params=list(CATALOG))
def physics(request):
    return WholeBodyPhysics.of(load_robot(request.param))


def smooth_path(nx, seed):
    rng = np.random.default_rng(seed)
    c = rng.normal(0, 0.3, (nx, 3))

    def at(t):
        x = c[:, 0] + c[:, 1] * np.sin(3 * t) + c[:, 2] * np.cos(5 * t)
        xd = 3 * c[:, 1] * np.cos(3 * t) - 5 * c[:, 2] * np.sin(5 * t)
        xdd = -9 * c[:, 1] * np.sin(3 * t) - 25 * c[:, 2] * np.cos(5 * t)
        return x, xd, xdd

    return at


def test_the_coordinates_map_to_pinocchios_state_and_its_derivatives(physics):
    path = smooth_path(physics.nx, seed=3)
    for t in (0.1, 0.7, 1.3):
        q, v, a = physics.pinocchio_state(*path(t))
        q_plus, v_plus, _ = physics.pinocchio_state(*path(t + FD_STEP_S))
        q_minus, v_minus, _ = physics.pinocchio_state(*path(t - FD_STEP_S))
        velocity = pin.difference(physics.model, q_minus, q_plus) / (2 * FD_STEP_S)
        np.testing.assert_allclose(v, velocity, rtol=0, atol=FD_TOL * max(1, np.abs(v).max()))
        acceleration = (v_plus - v_minus) / (2 * FD_STEP_S)
        np.testing.assert_allclose(a, acceleration, rtol=0, atol=FD_TOL * max(1, np.abs(a).max()))
        assert np.linalg.norm(q[3:7]) == pytest.approx(1.0, abs=1e-15)


def test_the_loads_are_pinocchios_rnea_with_the_contact_forces(physics):
    model, data = physics.model, physics.model.createData()
    fn = physics.node_function("paper")
    rng = np.random.default_rng(5)
    fids = [model.getFrameId(f) for f in physics.feet]
    for _ in range(5):
        x, xd, xdd = (rng.normal(0, 0.4, physics.nx) for _ in range(3))
        forces = rng.normal(0, physics.weight_n / 4, 12)
        out = dict(zip(fn.name_out(), fn(x, xd, xdd, forces), strict=True))
        q, v, a = physics.pinocchio_state(x, xd, xdd)
        pin.framesForwardKinematics(model, data, q)
        fext = [pin.Force.Zero() for _ in range(model.njoints)]
        for i, fid in enumerate(fids):
            frame = model.frames[fid]
            local = data.oMi[frame.parentJoint].rotation.T @ forces[3 * i : 3 * i + 3]
            fext[frame.parentJoint] += pin.Force(
                local, np.cross(frame.placement.translation, local)
            )
        reference = pin.rnea(model, data, q, v, a, fext)
        scale = max(1.0, np.abs(reference).max())
        np.testing.assert_allclose(
            np.array(out["base_wrench"]).ravel(), reference[:6], rtol=0, atol=TOL * scale
        )
        np.testing.assert_allclose(
            np.array(out["tau"]).ravel(), reference[6:], rtol=0, atol=TOL * scale
        )
        feet = np.array(out["feet_pos"])
        for i, fid in enumerate(fids):
            np.testing.assert_allclose(feet[:, i], data.oMf[fid].translation, atol=1e-12)


def test_every_joint_has_a_drive_and_says_where_it_comes_from(physics):
    assert len(physics.drives) == physics.n_joints == physics.nx - 6
    for drive, origin, name in zip(
        physics.drives, physics.drive_origins, physics.joint_names, strict=True
    ):
        assert drive.joint_name == name
        assert origin in (DRIVE_FROM_FILE, DRIVE_FROM_HIP, DRIVE_IDEAL)
    # each leg moves three joints, and every joint one leg
    assert sorted(physics.joint_legs) == sorted([0, 1, 2, 3] * 3)


def test_abduction_drives_are_the_hip_motor_on_electric_robots_and_ideal_on_scalf():
    go1 = WholeBodyPhysics.of(load_robot("go1"))
    hip = go1.drives[go1.joint_names.index("FR_hip_joint")]
    thigh = go1.drives[go1.joint_names.index("FR_thigh_joint")]
    assert isinstance(hip, ElectricDrive)
    assert hip.gear_ratio == thigh.gear_ratio
    assert go1.drive_origins[go1.joint_names.index("FR_hip_joint")] == DRIVE_FROM_HIP
    scalf = WholeBodyPhysics.of(load_robot("scalf"))
    assert scalf.drive_origins[scalf.joint_names.index("RF_hip_roll")] == DRIVE_IDEAL
    assert scalf.drive_origins[scalf.joint_names.index("RF_knee")] == DRIVE_FROM_FILE


def test_the_power_function_charges_what_the_node_function_charges():
    physics = WholeBodyPhysics.of(load_robot("scalf"))
    rng = np.random.default_rng(2)
    x, xd, xdd = (rng.normal(0, 0.3, physics.nx) for _ in range(3))
    forces = rng.normal(0, 500, 12)
    node = physics.node_function("paper")
    out = dict(zip(node.name_out(), node(x, xd, xdd, forces), strict=True))
    charged = physics.power_function("paper")(x, xd, out["tau"])
    np.testing.assert_allclose(np.array(charged), np.array(out["charged"]), rtol=1e-14)
    # the paper's accounting: |tau qd| plus the cylinders' friction heat, never negative
    assert (np.array(charged) >= 0).all()


@pytest.mark.parametrize("name, duty", [("go1", 0.35), ("scalf", 0.5)])
def test_the_kinematic_reference_trot_puts_the_feet_where_the_schedule_says(name, duty):
    from scalf_opt.locomotion.contact_schedule import trot_schedule
    from scalf_opt.locomotion.scaling import default_gait_for
    from scalf_opt.optimize.whole_body_start import START_LIFT_SHARE, starting_plan

    robot = load_robot(name)
    gait = default_gait_for(robot)
    physics = WholeBodyPhysics.of(robot)
    schedule = trot_schedule(gait.period_s, duty, 100.0)
    speed = gait.step_length_m / gait.period_s
    plan = starting_plan(physics, schedule, speed, gait.stance_height_m, gait.clearance_m)
    feet = plan.node_outputs("paper")["feet_pos"].reshape(3, -1, 4)  # (xyz, node, foot)
    for i in range(4):
        on = schedule.stance[i]
        back = schedule.previous_stance[i, on]
        np.testing.assert_allclose(feet[2, on, i], 0.0, atol=1e-9)
        np.testing.assert_allclose(
            feet[0, on, i], plan.footholds_m[0, i] - plan.stride_m * back, atol=1e-9
        )
        # the swing's apex is 1.1 H up, reached at mid-swing (a node when the swing is even)
        assert feet[2, ~on, i].max() == pytest.approx(START_LIFT_SHARE * gait.clearance_m, rel=0.02)
    # the trunk rides level at constant speed: its x advances one stride per cycle
    np.testing.assert_allclose(plan.x[0], speed * schedule.times_s, atol=1e-12)
    assert np.abs(plan.x[3:6]).max() == 0.0
    # the flying trot's forces: none in flight, the weight shared by the stance feet otherwise
    support = plan.forces_n[2::3].sum(axis=0)
    carried = schedule.loaded.any(axis=0)
    np.testing.assert_allclose(support[carried], physics.weight_n, rtol=1e-12)
    assert (support[~carried] == 0).all()


def test_the_plan_check_reads_pinocchios_torques_at_ten_times_the_rate():
    """Pinocchio's rnea at the nodes gives the twin's torques (an independent path); between
    them the check reads the spline, so the stance feet slide only by the spline's error."""
    from scalf_opt.locomotion.contact_schedule import trot_schedule
    from scalf_opt.locomotion.scaling import default_gait_for
    from scalf_opt.optimize.whole_body_start import starting_plan

    robot = load_robot("go1")
    gait = default_gait_for(robot)
    physics = WholeBodyPhysics.of(robot)
    schedule = trot_schedule(gait.period_s, 0.5, 200.0)
    plan = starting_plan(
        physics,
        schedule,
        gait.step_length_m / gait.period_s,
        gait.stance_height_m,
        gait.clearance_m,
    )
    check = plan.check("paper", factor=10)
    scale = np.abs(plan.evaluate("paper").tau_nm).max()
    assert check.torque_gap_nm < 1e-9 * scale
    assert check.energy.tau_nm.shape == (12, 10 * schedule.intervals)
    # the spline interpolates the nodes' joints to fourth order: sub-millimetre between nodes
    assert check.stance_slip_m < 1e-3
    assert check.swing_floor_m > -1e-3


@pytest.mark.parametrize("name", ["scalf", "go1"])
def test_a_joint_that_rests_at_every_node_is_charged_for_moving_between_them(name):
    """The plan's energy is Simpson's rule on the half intervals (nodes, quarter points and
    midpoints), so a motion that stops at every node (zero rates there, a C2 spline that moves
    between them) is charged as the ten-times re-reading through Pinocchio charges it; the nodes
    alone would charge none of it (the gap an optimizer exploits)."""
    from dataclasses import replace

    from scalf_opt.locomotion.contact_schedule import trot_schedule
    from scalf_opt.locomotion.periodic_spline import continuity_rows
    from scalf_opt.locomotion.scaling import default_gait_for
    from scalf_opt.optimize.whole_body_start import starting_plan

    robot = load_robot(name)
    gait = default_gait_for(robot)
    physics = WholeBodyPhysics.of(robot)
    schedule = trot_schedule(gait.period_s, 0.5, 40.0)
    n, h = schedule.intervals, schedule.step_s
    start = starting_plan(physics, schedule, 0.0, gait.stance_height_m, gait.clearance_m)
    still = replace(
        start,
        x=np.repeat(start.x[:, :1], n, axis=1),
        xd=np.zeros_like(start.xd),
        xdd=np.zeros_like(start.xdd),
    )
    # a knee that rests at every node: a_k = +-a, Y_{k+1} - Y_k = h^2 a_k / 6 (n is even)
    knee = 6 + physics.joint_names.index(robot.leg("RF").joint_names[-1])
    a = 0.3 / h**2  # a 0.05 rad step between nodes
    xdd = still.xdd.copy()
    xdd[knee] = a * (-1.0) ** np.arange(n)
    x = still.x.copy()
    x[knee] += np.where(np.arange(n) % 2 == 1, h**2 * a / 6, 0.0)
    moving = replace(still, x=x, xdd=xdd)
    values, rates = continuity_rows(x, moving.xd, xdd, h, moving.shift)
    assert np.abs(values).max() < 1e-12 and np.abs(rates).max() < 1e-9
    assert (moving.xd == 0).all()

    added = moving.evaluate("paper").total_j - still.evaluate("paper").total_j
    added_10x = moving.check("paper").energy.total_j - still.check("paper").energy.total_j
    assert added_10x > 1.0  # J per cycle: the motion between the nodes costs energy
    # Simpson's rule is exact for each interval's parabola of the rate and the cubic of a
    # motor's power; a cylinder's Stribeck heat is not a polynomial in the rate, so on SCalf the
    # rule reads this (Nyquist-rate) motion to about 10 %, against 100 % missed by the nodes
    assert added == pytest.approx(added_10x, rel=0.15)
