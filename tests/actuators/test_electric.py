"""The electric drive: a hand-computed case, regeneration, the energy balance over a periodic
motion against Pinocchio's torques, smoothing and its derivatives against finite differences."""

import math

import casadi as ca
import numpy as np
import pinocchio as pin
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from scalf_opt.actuators.electric import POWER_SCALE_W, ElectricDrive, direction
from scalf_opt.actuators.stribeck import smooth_max
from scalf_opt.energy.physics import LegPhysics, trapezoid_weights
from scalf_opt.model.kinematics import LegKinematics

MOTOR = ElectricDrive(
    joint_name="j",
    gear_ratio=9.0,
    torque_constant_nm_per_a=0.025,
    winding_resistance_ohm=0.3,
    coulomb_friction_nm=0.03,
    viscous_friction_nm_s_per_rad=0.001,
)


def smooth(eps=1e-4):
    return lambda x, _: smooth_max(x, eps)


def test_a_case_by_hand():
    tau, qd = 1.2, 3.0
    friction = 0.03 * 1.0 + 0.001 * 3.0  # Coulomb in the direction of motion, plus viscous
    current = (tau + friction) / (9.0 * 0.025)
    copper = 0.3 * current**2
    electric = (tau + friction) * qd + copper
    out = MOTOR.outputs(0.0, qd, tau)
    assert float(out["motor_current"]) == pytest.approx(current, rel=1e-14)
    assert float(out["copper_loss"]) == pytest.approx(copper, rel=1e-14)
    assert float(out["electric_power"]) == pytest.approx(electric, rel=1e-14)
    assert float(MOTOR.loss_rate(0.0, qd, tau)) == pytest.approx(electric, rel=1e-14)
    assert not MOTOR.charges_joint_power  # the drive meters what it draws


def test_braking_costs_nothing_without_regeneration_and_pays_back_with_it():
    tau, qd = -1.2, 10.0  # the joint brakes: the motor generates more than it heats
    electric = float(MOTOR.electric_power_w(qd, tau))
    assert electric < 0
    assert float(MOTOR.loss_rate(0.0, qd, tau)) == 0.0
    regen = ElectricDrive(**{**MOTOR.__dict__, "regenerative": True})
    assert float(regen.loss_rate(0.0, qd, tau)) == pytest.approx(electric, rel=1e-14)


def test_sign_and_standstill():
    assert [float(direction(x)) for x in (-2.0, 0.0, 3.0)] == [-1.0, 0.0, 1.0]
    # at rest the friction is zero and the motor only heats: P = R (tau / (N k_t))^2
    assert float(MOTOR.loss_rate(0.0, 0.0, 0.9)) == pytest.approx(0.3 * (0.9 / 0.225) ** 2)


@settings(max_examples=80, deadline=None)
@given(qd=st.floats(-20, 20), tau=st.floats(-3, 3))
def test_drawn_power_covers_the_work_and_the_heat(qd, tau):
    # first law: bus power = joint work + copper loss + friction heat, burnt surplus when braking
    heat = 0.03 * abs(qd) + 0.001 * qd**2
    drawn = float(MOTOR.loss_rate(0.0, qd, tau))
    copper = float(MOTOR.copper_loss_w(qd, tau))
    assert drawn >= 0.0
    assert drawn >= tau * qd + copper + heat - 1e-12 * (1 + abs(tau * qd))


def test_energy_balance_over_a_periodic_motion_against_pinocchio(solo12):
    # regenerative drives over a periodic joint motion: the rigid body's work integrates to zero,
    # so the energy drawn is the copper loss plus the friction heat, both recomputed here from
    # Pinocchio's inverse dynamics
    leg = solo12.leg("RF")
    regen = {
        j: ElectricDrive(j, 9.0, 0.025, 0.3, 0.03, 0.001, regenerative=True)
        for j in leg.joint_names
    }
    physics = LegPhysics(LegKinematics(leg), (regen[leg.joint_names[0]], regen[leg.joint_names[1]]))
    period, n = 0.3, 1201
    t = np.linspace(0.0, period, n)
    w = 2 * np.pi / period
    q0, a, b = np.array([0.8, -1.6]), np.array([0.3, 0.4]), np.array([0.1, -0.2])
    q = q0[:, None] + a[:, None] * np.sin(w * t) + b[:, None] * np.cos(2 * w * t)
    qd = a[:, None] * w * np.cos(w * t) - b[:, None] * 2 * w * np.sin(2 * w * t)
    qdd = -a[:, None] * w**2 * np.sin(w * t) - b[:, None] * 4 * w**2 * np.cos(2 * w * t)
    fn = physics.sample_function("joint").map(n)
    out = dict(zip(physics.output_names, fn(q, qd, qdd, np.zeros((2, n))), strict=True))
    weights = trapezoid_weights(t)
    drawn = float((np.array(out["power"]) @ weights).sum())
    data = leg.model.createData()
    tau = np.column_stack(
        [pin.rnea(leg.model, data, q[:, k], qd[:, k], qdd[:, k]) for k in range(n)]
    )
    load = tau + 0.03 * np.sign(qd) + 0.001 * qd
    copper = 0.3 * (load / (9.0 * 0.025)) ** 2
    heat = 0.03 * np.abs(qd) + 0.001 * qd**2
    expected = float(((copper + heat) @ weights).sum())
    gross = float((np.abs(tau * qd) @ weights).sum())
    # the trapezoidal rule integrates the periodic work to round-off; the kinks of |qd| at its
    # zero crossings cost O(h^2) of the friction heat: 1e-6 of the gross work covers both
    assert drawn == pytest.approx(expected, abs=1e-6 * gross)
    assert expected > 0.01 * drawn  # the check is not empty: losses are a real part of it


@pytest.mark.parametrize("regenerative", [False, True])
def test_smooth_loss_has_the_finite_difference_gradient(regenerative):
    drive = ElectricDrive(**{**MOTOR.__dict__, "regenerative": regenerative})
    qd, tau = ca.SX.sym("qd"), ca.SX.sym("tau")
    loss = drive.loss_rate(0.0, qd, tau, smooth())
    fn = ca.Function("f", [qd, tau], [loss, ca.gradient(loss, ca.vertcat(qd, tau))])
    h = 1e-6
    for qd0, tau0 in ((2.0, 0.5), (-1.5, 0.4), (0.004, -0.2), (3.0, -0.05)):
        _, grad = fn(qd0, tau0)
        fd = [
            (float(fn(qd0 + h, tau0)[0]) - float(fn(qd0 - h, tau0)[0])) / (2 * h),
            (float(fn(qd0, tau0 + h)[0]) - float(fn(qd0, tau0 - h)[0])) / (2 * h),
        ]
        # central differences: truncation h^2 |f'''| (f''' up to 1e9 inside the 0.01 rad/s
        # smoothing of sign(qd)) and round-off eps |f| / h ~ 1e-9: 1e-5 relative
        np.testing.assert_allclose(np.array(grad).ravel(), fd, rtol=1e-5, atol=1e-7)


def test_smooth_loss_approaches_the_exact_one():
    states = [(2.0, 0.5), (-1.5, 0.4), (3.0, -0.05), (0.5, 0.0)]
    for qd, tau in states:
        exact = float(MOTOR.loss_rate(0.0, qd, tau))
        gaps = [
            abs(float(MOTOR.loss_rate(0.0, qd, tau, smooth(eps))) - exact) for eps in (1e-4, 1e-6)
        ]
        # away from the kinks the smooth max is within eps^2 / (4 |x|) of the exact one
        assert gaps[1] <= gaps[0] + 1e-15
        assert gaps[0] <= 0.5e-4 * POWER_SCALE_W + 1e-3
    assert math.isclose(float(direction(0.7, lambda x, _: smooth_max(x, 1e-9))), 1.0, rel_tol=1e-12)
