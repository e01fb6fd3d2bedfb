"""The CasADi twin with a floating base, against Pinocchio's free-flyer model of every robot.

The first brick of the 3-D whole-body model: the base's position and unit quaternion, its
velocity and acceleration in its own frame, every joint of the URDF (abduction included), and
point contact forces at the feet. Checked on random states against ``pin.rnea`` (with the
forces as ``fext`` on the feet's parent joints), ``pin.crba`` and ``pin.computeFrameJacobian``.
"""

import casadi as ca
import numpy as np
import pinocchio as pin
import pytest

from scalf_opt.model.symbolic import SymbolicChain
from scalf_opt.model.urdf_file import read_urdf_text
from scalf_opt.robots.catalog import CATALOG
from scalf_opt.robots.loading import load_robot
from scalf_opt.types import LEG_NAMES

N_STATES = 20
TOL = 1e-9  # relative to max(1, |reference|): exact maths, round-off only (forces of kN)


def close(actual, expected):
    expected = np.array(expected, dtype=float)
    actual = np.array(actual, dtype=float).reshape(expected.shape)
    scale = max(1.0, float(np.abs(expected).max()))
    np.testing.assert_allclose(actual, expected, rtol=0, atol=TOL * scale)


def floating(name):
    robot = load_robot(name)
    model = pin.buildModelFromXML(read_urdf_text(robot.urdf_path), pin.JointModelFreeFlyer())
    feet = tuple(robot.leg(leg).foot_frame for leg in LEG_NAMES)
    return model, feet


def states(model, seed):
    rng = np.random.default_rng(seed)
    lo = np.maximum(model.lowerPositionLimit[7:], -np.pi)
    hi = np.minimum(model.upperPositionLimit[7:], np.pi)
    for _ in range(N_STATES):
        quat = rng.normal(size=4)
        q = np.concatenate(
            [rng.normal(0, 0.5, 3), quat / np.linalg.norm(quat), rng.uniform(lo, hi)]
        )
        yield q, rng.normal(0, 2, model.nv), rng.normal(0, 2, model.nv), rng.normal(0, 300, 12)


@pytest.mark.parametrize("name", list(CATALOG))
def test_the_floating_twin_is_pinocchios_free_flyer(name):
    model, feet = floating(name)
    twin = SymbolicChain(model)
    contact = twin.contact_rnea(feet)
    data = model.createData()
    fids = [model.getFrameId(f) for f in feet]
    q_sym = ca.SX.sym("q", model.nq)
    jacobian = ca.Function("J", [q_sym], [twin.frame_jacobian(q_sym, feet[0])])
    for q, v, a, f in states(model, seed=11):
        close(twin.rnea(q, v, a), pin.rnea(model, data, q, v, a))
        close(twin.crba(q), pin.crba(model, data, q))
        close(
            jacobian(q), pin.computeFrameJacobian(model, data, q, fids[0], pin.LOCAL_WORLD_ALIGNED)
        )
        pin.forwardKinematics(model, data, q)
        pin.updateFramePlacements(model, data)
        fext = [pin.Force.Zero() for _ in range(model.njoints)]
        for k, fid in enumerate(fids):
            frame = model.frames[fid]
            rot = data.oMi[frame.parentJoint].rotation
            local = rot.T @ f[3 * k : 3 * k + 3]  # world force at the foot, in the joint's axes
            moment = np.cross(frame.placement.translation, local)
            fext[frame.parentJoint] += pin.Force(local, moment)
        close(contact(q, v, a, f), pin.rnea(model, data, q, v, a, fext))


def test_forces_that_carry_the_robot_leave_the_base_no_wrench():
    """Standing still on four feet: the feet's forces that balance the weight (a least-squares
    split of the base's wrench) zero the base's six rows, and the joints then hold it."""
    model, feet = floating("go1")
    twin = SymbolicChain(model)
    contact = twin.contact_rnea(feet)
    q = pin.neutral(model)
    v = a = np.zeros(model.nv)
    base = np.array(twin.rnea(q, v, a)).ravel()[:6]
    # the base rows are linear in the forces: solve for the minimum-norm forces
    zero = np.zeros(12)
    columns = [np.array(contact(q, v, a, e)).ravel()[:6] - base for e in np.eye(12)]
    forces = np.linalg.lstsq(np.array(columns).T, -base, rcond=None)[0]
    tau = np.array(contact(q, v, a, forces)).ravel()
    np.testing.assert_allclose(tau[:6], 0.0, atol=1e-9 * np.abs(base).max())
    # vertical forces add up to the weight
    weight = -model.gravity.linear[2] * sum(i.mass for i in model.inertias)
    assert forces[2::3].sum() == pytest.approx(weight, rel=1e-9)
    assert np.array(contact(q, v, a, zero)).ravel()[:6] == pytest.approx(base, rel=1e-12)
