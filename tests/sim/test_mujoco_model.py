"""The MuJoCo model is the URDF's robot: the same masses, inertias, axes and limits as Pinocchio.

Pinocchio builds the same robot independently from the URDF: a planar root joint (slide x, slide
z, rotation about y, as a composite joint) and every joint but the legs' hip pitch and knee
locked at zero. On random states (robot in the air, no contact), MuJoCo's joint-space mass matrix
and inverse dynamics must equal Pinocchio's CRBA and RNEA.
"""

import mujoco
import numpy as np
import pinocchio as pin
import pytest

from scalf_opt.robots.loading import load_robot
from scalf_opt.sim.mujoco_model import TRUNK_JOINTS, build_sim_model
from scalf_opt.sim.settings import SimSettings
from scalf_opt.types import LEG_NAMES


def planar_pinocchio(robot):
    root = pin.JointModelComposite()
    root.addJoint(pin.JointModelPX())
    root.addJoint(pin.JointModelPZ())
    root.addJoint(pin.JointModelRY())
    full = pin.buildModelFromUrdf(str(robot.urdf_path), root)
    keep = {name for leg in LEG_NAMES for name in robot.leg(leg).joint_names} | {"root_joint"}
    lock = [i for i in range(1, full.njoints) if full.names[i] not in keep]
    return pin.buildReducedModel(full, lock, pin.neutral(full))


def pinocchio_order(model, sim):
    """MuJoCo dof index of each Pinocchio velocity coordinate."""
    order = list(sim.trunk_dof)
    for i in range(2, model.njoints):
        name = model.names[i]
        order.append(int(sim.model.jnt_dofadr[sim.model.joint(name).id]))
    return np.array(order)


@pytest.mark.parametrize("name", ["scalf", "solo12", "hyq", "go1"])
def test_mass_matrix_and_inverse_dynamics_equal_pinocchio(name):
    robot = load_robot(name)
    sim = build_sim_model(robot, SimSettings())
    model = planar_pinocchio(robot)
    data = model.createData()
    order = pinocchio_order(model, sim)
    mj = sim.model
    # the URDF's joint friction and damping (Go1, HyQ) are the drives' in the energy model: not
    # in the simulated mechanics, so the inverse dynamics are the rigid bodies' alone
    assert not mj.dof_frictionloss.any() and not mj.dof_damping.any()
    mjd = mujoco.MjData(mj)
    rng = np.random.default_rng(11)
    lower = np.array(
        [mj.jnt_range[mj.joint(model.names[i]).id][0] for i in range(2, model.njoints)]
    )
    upper = np.array(
        [mj.jnt_range[mj.joint(model.names[i]).id][1] for i in range(2, model.njoints)]
    )
    scale = np.abs(pin.crba(model, data, pin.neutral(model))).max()
    for _ in range(25):
        q = np.concatenate(
            [
                [rng.uniform(-1, 1), rng.uniform(3, 5), rng.uniform(-0.5, 0.5)],
                rng.uniform(lower, upper),
            ]
        )
        v, a = rng.normal(0, 2, model.nv), rng.normal(0, 10, model.nv)
        mjd.qpos[order] = q  # one qpos per dof here (slides and hinges)
        mjd.qvel[order] = v
        mjd.qacc[order] = a
        mujoco.mj_inverse(mj, mjd)
        assert mjd.ncon == 0
        full = np.zeros((mj.nv, mj.nv))
        mujoco.mj_fullM(mj, mjd, full)
        mass = pin.crba(model, data, q)
        mass = np.triu(mass) + np.triu(mass, 1).T
        # exact maths on both sides: round-off only (HyQ's dropped 1e-6 kg m^2 products of
        # inertia sit on links of 1e-6 kg, far below it)
        tol = 1e-12
        np.testing.assert_allclose(full[np.ix_(order, order)], mass, rtol=0, atol=tol * scale)
        tau = pin.rnea(model, data, q, v, a)
        np.testing.assert_allclose(
            mjd.qfrc_inverse[order], tau, rtol=0, atol=tol * np.abs(tau).max()
        )


def test_the_model_has_the_sagittal_trunk_and_round_feet():
    robot = load_robot("scalf")
    sim = build_sim_model(robot, SimSettings())
    mj = sim.model
    assert [mj.joint(i).name for i in range(3)] == list(TRUNK_JOINTS)
    assert mj.nq == mj.nv == 3 + 8
    assert sim.total_mass_kg == pytest.approx(robot.total_mass_kg, rel=1e-12)
    # nearly point feet, as the energy model assumes: 0.5 % of the leg length
    assert sim.foot_radius_m == pytest.approx(0.005 * robot.leg_length_m, rel=1e-12)
    for leg in LEG_NAMES:
        joint_ids = [mj.joint(name).id for name in robot.leg(leg).joint_names]
        np.testing.assert_array_equal(
            mj.jnt_range[joint_ids][:, 0], robot.leg(leg).lower_limits_rad
        )
        np.testing.assert_array_equal(
            mj.jnt_range[joint_ids][:, 1], robot.leg(leg).upper_limits_rad
        )
        # the foot sphere sits at Pinocchio's foot frame
        data = mujoco.MjData(mj)
        mujoco.mj_kinematics(mj, data)
        pin_leg = robot.leg(leg)
        pdata = pin_leg.model.createData()
        pin.framesForwardKinematics(pin_leg.model, pdata, np.zeros(2))
        np.testing.assert_allclose(
            data.geom_xpos[sim.foot_geom[leg]],
            pdata.oMf[pin_leg.foot_frame_id].translation,
            atol=1e-12,
        )


def test_settings_refuse_an_unstable_servo_and_a_too_soft_step():
    from scalf_opt.errors import ConfigError

    with pytest.raises(ConfigError, match="servo_bandwidth_hz"):
        SimSettings(timestep_s=0.0005, servo_bandwidth_hz=100.0)
    with pytest.raises(ConfigError, match="contact_time_constant_s"):
        SimSettings(timestep_s=0.0005, contact_time_constant_s=0.0005)
    with pytest.raises(ConfigError, match="foot_friction"):
        SimSettings(foot_friction=-1.0)


def test_anymal_cs_unphysical_camera_inertias_are_balanced_and_reported():
    """MuJoCo refuses ANYmal C's depth cameras (A + B < C); balanceinertia repairs them."""
    robot = load_robot("anymal_c")
    sim = build_sim_model(robot, SimSettings())
    cameras = [r for r in sim.repairs if "balanceinertia" in r]
    assert len(cameras) == 4
    assert all(r.startswith("link depth_camera_") for r in cameras)
    assert sim.total_mass_kg == pytest.approx(robot.total_mass_kg, rel=1e-12)
    assert build_sim_model(load_robot("scalf"), SimSettings()).repairs == ()


def test_the_referee_is_scaled_to_the_robot():
    """Servo frequency ~ sqrt(g / L), contact time ~ sqrt(L / g): SCalf keeps 30 Hz and 2 ms."""
    scalf, go1 = (load_robot(n).leg_length_m for n in ("scalf", "go1"))
    s, how = SimSettings().for_leg_length(scalf)
    g, _ = SimSettings().for_leg_length(go1)
    assert s.servo_bandwidth_hz == pytest.approx(30.0, rel=1e-3)
    assert s.contact_time_constant_s == pytest.approx(0.002, rel=1e-3)
    assert g.servo_bandwidth_hz / s.servo_bandwidth_hz == pytest.approx((scalf / go1) ** 0.5)
    assert g.contact_time_constant_s / s.contact_time_constant_s == pytest.approx(
        (go1 / scalf) ** 0.5
    )
    assert set(how) == {
        "timestep_s",
        "servo_bandwidth_hz",
        "contact_time_constant_s",
        "foot_radius_m",
    }
    given, how = SimSettings(servo_bandwidth_hz=20.0).for_leg_length(scalf)
    assert given.servo_bandwidth_hz == 20.0 and "servo_bandwidth_hz" not in how
    # a given time step limits the servo and the contact, and the derivation says so
    tiny, how = SimSettings(timestep_s=0.0005).for_leg_length(0.02)
    assert tiny.contact_time_constant_s == 2 * tiny.timestep_s
    assert "raised" in how["contact_time_constant_s"] and "lowered" in how["servo_bandwidth_hz"]
    # else the step follows them: 0.5 ms on SCalf, finer for a fast servo
    assert s.timestep_s == 0.0005
    fast, how = SimSettings(servo_bandwidth_hz=200.0).for_leg_length(scalf)
    assert 2 * np.pi * 200.0 * fast.timestep_s == pytest.approx(0.2, rel=1e-12)
