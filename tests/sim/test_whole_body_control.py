"""The 3-D referee's controller, one step at a time (no simulation).

Its parts checked against what they must do: the stance forces' QP against the trunk's equations
and the friction pyramid, the swing targets against the plan when the robot is on it, the
torques against ``tau_ff - J_q^T df``.
"""

import numpy as np
import pinocchio as pin
import pytest

from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.locomotion.contact_schedule import trot_schedule
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.optimize.whole_body_nlp import CycleProblem, kinematic_start
from scalf_opt.robots.loading import load_robot
from scalf_opt.sim.settings import SimSettings
from scalf_opt.sim.whole_body_control import WholeBodyController, whole_body_gains


@pytest.fixture(scope="module")
def setup():
    physics = WholeBodyPhysics.of(load_robot("go1"))
    gait = default_gait_for(physics.robot)
    schedule = trot_schedule(gait.period_s, 0.5, 50.0)
    problem = CycleProblem(
        physics, schedule, gait.speed_m_s, gait.stance_height_m, gait.clearance_m
    )
    plan = kinematic_start(problem)
    samples = plan.samples(np.array([0.25 * gait.period_s]))  # mid-stance of RF and LH
    settings, _ = SimSettings().for_leg_length(physics.robot.leg_length_m)
    gains = whole_body_gains(physics, samples.q[:, 0], settings, 0.8, gait.stance_height_m)
    controller = WholeBodyController(physics, gains, np.full(physics.n_joints, np.inf))
    return physics, samples, controller


def _jacobians(physics, q):
    model = physics.model
    data = model.createData()
    pin.computeJointJacobians(model, data, q)
    pin.updateFramePlacements(model, data)
    return data, [
        pin.getFrameJacobian(model, data, model.getFrameId(f), pin.LOCAL_WORLD_ALIGNED)[:3]
        for f in physics.feet
    ]


def _torques(setup, q, stance, progress):
    """The controller's output at configuration ``q``, the plan's rates, plan and feet."""
    physics, s, controller = setup
    data, _ = _jacobians(physics, q)
    feet = np.array([data.oMf[physics.model.getFrameId(f)].translation for f in physics.feet]).T
    return controller.torques(
        q, s.v[:, 0], s.q[:, 0], s.v[:, 0], s.tau_nm[:, 0], s.forces_n[:, 0], feet, stance, progress
    )


def test_on_the_plan_the_torques_are_the_plan_s(setup):
    _, s, _ = setup
    stance = np.array([True, True, False, False])
    out = _torques(setup, s.q[:, 0], stance, np.array([0.0, 0.0, 0.5, 0.5]))
    # no error: no feedback, no extra force; a swing target's Newton step is zero
    np.testing.assert_allclose(out.feedback_nm, 0.0, atol=1e-9)
    np.testing.assert_allclose(out.extra_force_n, 0.0, atol=1e-9)
    np.testing.assert_allclose(out.tau_nm, s.tau_nm[:, 0], rtol=0, atol=1e-9)


@pytest.mark.parametrize(
    "stance", [(True, True, True, True), (True, True, False, False), (False, False, True, True)]
)
def test_the_qp_s_forces_fit_the_trunk_s_wrench_inside_the_pyramid(setup, stance):
    physics, s, controller = setup
    stance = np.array(stance)
    q = s.q[:, 0]
    _, jacobians = _jacobians(physics, q)
    a = np.hstack([jac[:, :6].T for jac in jacobians])
    plan_forces = np.where(np.repeat(stance, 3), np.tile([5.0, -3.0, 60.0], 4), 0.0)
    wrench = np.array([8.0, -5.0, 20.0, 1.5, -2.0, 0.7])  # trunk axes [N, N m]
    df = controller._extra_forces(wrench, jacobians, plan_forces, stance)
    forces = (plan_forces + df).reshape(4, 3)
    mu = controller.gains.friction
    for i in range(4):
        if not stance[i]:
            np.testing.assert_array_equal(df[3 * i : 3 * i + 3], 0.0)
            continue
        assert forces[i, 2] >= -1e-9
        assert abs(forces[i, 0]) <= mu * forces[i, 2] + 1e-9
        assert abs(forces[i, 1]) <= mu * forces[i, 2] + 1e-9
    on = np.repeat(stance, 3)
    achievable = a[:, on]
    if stance.all():
        # four feet span every wrench: the small weight on the force's size is all that is left
        np.testing.assert_allclose(a @ df, wrench, rtol=0, atol=1e-3 * np.abs(wrench).max())
    else:
        # two feet: the fit is the wrench's weighted projection on what they can push; the part
        # left is the moment about the line of the feet, which no force of theirs has
        weight = np.r_[np.ones(3), np.full(3, 1.0 / controller.gains.moment_arm_m)]
        left = weight * (a @ df - wrench)
        scaled = weight[:, None] * achievable
        assert np.abs(scaled.T @ left).max() < 1e-3 * np.abs(scaled.T @ (weight * wrench)).max()


def test_stance_joints_carry_the_extra_forces(setup):
    physics, s, _ = setup
    stance = np.array([True, True, False, False])
    q = s.q[:, 0].copy()
    q[2] -= 0.01  # the trunk 1 cm low: the loop asks for more upward force
    _, jacobians = _jacobians(physics, q)
    out = _torques(setup, q, stance, np.zeros(4))
    assert out.extra_force_n[2] > 0 and out.extra_force_n[5] > 0
    legs = np.array(physics.joint_legs)
    for i in (0, 1):
        joints = np.flatnonzero(legs == i)
        expected = -jacobians[i][:, 6 + joints].T @ out.extra_force_n[3 * i : 3 * i + 3]
        np.testing.assert_allclose(out.feedback_nm[joints], expected, rtol=1e-12, atol=1e-12)
