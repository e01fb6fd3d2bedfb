"""The sagittal leg: Pinocchio against the closed-form Lagrangian; kinematics round trips."""

import math

import numpy as np
import pinocchio as pin
import pytest

from scalf_opt.errors import InfeasibleError, ModelError
from scalf_opt.model.kinematics import LegKinematics
from scalf_opt.robots.loading import load_robot

# Table 1, written here independently of the code under test.
M1, M2 = 4.10, 2.24
L1, L2 = 0.45099, 0.40487
LM1, LM2 = 0.21043, 0.22720
EPS1, EPS2 = 0.037, -0.083
I1, I2 = 0.178, 0.057
G = 9.81


def lagrangian_torques(q, qd, qdd, mirror):
    """Eq. 10-28: two-link leg rotating about +y, COM angles negated for a hind leg."""
    e1, e2 = (-EPS1, -EPS2) if mirror else (EPS1, EPS2)
    t1, t2 = q
    c2 = math.cos(t2 + e2)
    s2 = math.sin(t2 + e2)
    m11 = I1 + M1 * LM1**2 + I2 + M2 * (L1**2 + LM2**2 + 2 * L1 * LM2 * c2)
    m12 = I2 + M2 * (LM2**2 + L1 * LM2 * c2)
    m22 = I2 + M2 * LM2**2
    h = -M2 * L1 * LM2 * s2
    coriolis = np.array([h * (2 * qd[0] * qd[1] + qd[1] ** 2), -h * qd[0] ** 2])
    gravity = G * np.array(
        [
            M1 * LM1 * math.sin(t1 + e1) + M2 * (L1 * math.sin(t1) + LM2 * math.sin(t1 + t2 + e2)),
            M2 * LM2 * math.sin(t1 + t2 + e2),
        ]
    )
    mass = np.array([[m11, m12], [m12, m22]])
    return mass @ qdd + coriolis + gravity, mass


def random_states(leg, n, seed):
    rng = np.random.default_rng(seed)
    lo, hi = leg.lower_limits_rad, leg.upper_limits_rad
    for _ in range(n):
        yield rng.uniform(lo, hi), rng.normal(0, 3, 2), rng.normal(0, 30, 2)


@pytest.mark.parametrize("name", ["RF", "LH", "LF", "RH"])
def test_pinocchio_equals_closed_form_lagrangian(scalf, name):
    leg = scalf.leg(name)
    data = leg.model.createData()
    for q, qd, qdd in random_states(leg, 100, seed=1):
        expected, mass = lagrangian_torques(q, qd, qdd, leg.is_hind)
        tau = pin.rnea(leg.model, data, q, qd, qdd)
        np.testing.assert_allclose(tau, expected, rtol=1e-9, atol=1e-9 * np.abs(expected).max())
        m = pin.crba(leg.model, data, q)
        np.testing.assert_allclose(np.triu(m) + np.triu(m, 1).T, mass, rtol=1e-9)


def test_leg_geometry_matches_table_1(scalf):
    for name in ("RF", "LH"):
        leg = scalf.leg(name)
        assert leg.thigh_length_m == pytest.approx(L1, abs=1e-12)
        assert leg.shank_length_m == pytest.approx(L2, abs=1e-12)
        assert leg.axis_signs == (1, 1)
        assert leg.is_hind == (name == "LH")
    rf = scalf.leg("RF")
    np.testing.assert_allclose(rf.hip_origin_m, [0.68, -0.257, -0.195], atol=1e-12)


def test_ik_branch_is_the_one_of_the_reference_posture(scalf, hyq, solo12):
    # SCalf has no SRDF: its reference is mid-range (front knee bent forward, q_knee > 0); HyQ
    # and Solo12 stand as their SRDF's "standing" state says (front knee q = -1.5 and -1.6 rad)
    expected = {"hyq": (0.75, -1.5), "solo12": (0.8, -1.6)}
    for robot in (scalf, hyq, solo12):
        for name in ("RF", "LH"):
            leg = robot.leg(name)
            kin = LegKinematics(leg)
            q_ref = leg.reference_posture_rad
            if robot.name in expected:
                mirror = -1.0 if name == "LH" else 1.0
                np.testing.assert_allclose(q_ref, mirror * np.array(expected[robot.name]))
            else:
                np.testing.assert_allclose(
                    q_ref, 0.5 * (leg.lower_limits_rad + leg.upper_limits_rad)
                )
            np.testing.assert_allclose(kin.inverse(kin.forward(q_ref)), q_ref, atol=1e-12)


def workspace_points(leg, n, seed):
    """Random foot targets reachable inside the joint limits (FK of random angles)."""
    rng = np.random.default_rng(seed)
    kin = LegKinematics(leg)
    q = rng.uniform(leg.lower_limits_rad, leg.upper_limits_rad, size=(n, 2)).T
    return kin, q, kin.forward(q)


@pytest.mark.parametrize("name", ["RF", "LH"])
def test_fk_ik_round_trip(scalf, name):
    leg = scalf.leg(name)
    kin, q, p = workspace_points(leg, 500, seed=2)
    q_ik = kin.inverse(p)
    np.testing.assert_allclose(kin.forward(q_ik), p, rtol=0, atol=1e-12)
    # the IK's fixed branch is the one the joint limits allow: it recovers the sampled angles
    np.testing.assert_allclose(q_ik, q, atol=1e-9)


@pytest.mark.parametrize(("robot", "leg"), [("hyq", "RF"), ("hyq", "LH"), ("solo12", "RF")])
def test_ik_works_unchanged_on_other_robots(robot, leg, request):
    robot_model = request.getfixturevalue(robot)
    leg_model = robot_model.leg(leg)
    kin = LegKinematics(leg_model)
    h = robot_model.nominal_stance_height_m
    p = np.array([[0.05, -0.05, 0.1], [-h, -h, -0.9 * h]])
    np.testing.assert_allclose(kin.forward(kin.inverse(p)), p, atol=1e-12)


def test_jacobian_against_pinocchio_and_finite_differences(scalf):
    leg = scalf.leg("RF")
    kin = LegKinematics(leg)
    data = leg.model.createData()
    rng = np.random.default_rng(4)
    for _ in range(50):
        q = rng.uniform(leg.lower_limits_rad, leg.upper_limits_rad)
        qd = rng.normal(0, 3, 2)
        jac = pin.computeFrameJacobian(
            leg.model, data, q, leg.foot_frame_id, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        )[[0, 2]]
        np.testing.assert_allclose(kin.jacobian(q), jac, atol=1e-12)
        # dJ/dt along qd by central differences of J(q + h qd); h = 1e-6 gives truncation
        # ~h^2 |d3J| ~ 1e-12 and round-off ~eps |J| / h ~ 1e-10: tolerance 1e-8
        h = 1e-6
        fd = (kin.jacobian(q + h * qd) - kin.jacobian(q - h * qd)) / (2 * h)
        np.testing.assert_allclose(kin.jacobian_dot(q, qd), fd, atol=1e-8)


def test_joint_motion_matches_pinocchio_classical_acceleration(scalf):
    leg = scalf.leg("LH")
    kin = LegKinematics(leg)
    data = leg.model.createData()
    q, qd, qdd = np.array([0.4, -1.1]), np.array([2.0, -3.0]), np.array([10.0, 5.0])
    pin.forwardKinematics(leg.model, data, q, qd, qdd)
    pin.updateFramePlacements(leg.model, data)
    acc = pin.getFrameClassicalAcceleration(
        leg.model, data, leg.foot_frame_id, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    ).linear[[0, 2]]
    vel = kin.jacobian(q) @ qd
    p = kin.forward(q)
    q2, qd2, qdd2 = kin.joint_motion(p[:, None], vel[:, None], acc[:, None])
    np.testing.assert_allclose(q2.ravel(), q, atol=1e-12)
    np.testing.assert_allclose(qd2.ravel(), qd, atol=1e-11)
    np.testing.assert_allclose(qdd2.ravel(), qdd, atol=1e-9)


def test_unreachable_target_names_point_and_reach(scalf):
    kin = LegKinematics(scalf.leg("RF"))
    with pytest.raises(
        InfeasibleError, match=r"x=0\.0000 m, z=-0\.9000 m.*reach \[0\.0461, 0\.8559\]"
    ):
        kin.inverse(np.array([[0.0], [-0.9]]))


def test_bad_urdf_and_leg_names(tmp_path, scalf):
    with pytest.raises(ModelError, match="not found"):
        load_robot(urdf=tmp_path / "missing.urdf")
    bad = tmp_path / "bad.urdf"
    bad.write_text("<robot name='x'><link name='a'/></robot>")
    with pytest.raises(ModelError, match=r"bad\.urdf"):
        load_robot(urdf=bad)
    with pytest.raises(ModelError, match="unknown leg 'XX'"):
        scalf.leg("XX")
