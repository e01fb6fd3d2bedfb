"""The CasADi twin against Pinocchio, on SCalf, HyQ and Solo12 legs and whole robots."""

import casadi as ca
import numpy as np
import pinocchio as pin
import pytest

from scalf_opt.errors import ModelError
from scalf_opt.model.symbolic import SymbolicChain
from scalf_opt.robots.loading import load_robot

N_STATES = 100
TOL = 1e-10  # absolute, scaled by max(1, |reference|): the maths is exact, round-off only

CASES = [
    ("scalf", "RF"),
    ("scalf", "LH"),
    ("hyq", "RF"),
    ("hyq", "LH"),
    ("solo12", "RF"),
    ("solo12", "LH"),
]


def close(actual, expected):
    actual, expected = np.array(actual, dtype=float), np.array(expected, dtype=float)
    scale = max(1.0, float(np.abs(expected).max()))
    np.testing.assert_allclose(actual, expected, rtol=0, atol=TOL * scale)


def states(model, seed):
    rng = np.random.default_rng(seed)
    lo = np.maximum(model.lowerPositionLimit, -np.pi)
    hi = np.minimum(model.upperPositionLimit, np.pi)
    for _ in range(N_STATES):
        yield rng.uniform(lo, hi), rng.normal(0, 3, model.nv), rng.normal(0, 3, model.nv)


def check_against_pinocchio(model, frame):
    twin = SymbolicChain(model)
    fns = twin.functions(frame)
    q_sym = ca.SX.sym("q", model.nq)
    frames = {
        ref: ca.Function("J", [q_sym], [twin.frame_jacobian(q_sym, frame, ref)])
        for ref in ("LOCAL_WORLD_ALIGNED", "WORLD", "LOCAL")
    }
    placement = ca.Function("oMf", [q_sym], list(twin.frame_placement(q_sym, frame)))
    data = model.createData()
    fid = model.getFrameId(frame)
    for q, v, a in states(model, seed=5):
        pin.forwardKinematics(model, data, q)
        pin.updateFramePlacements(model, data)
        rot, _ = placement(q)
        close(rot, data.oMf[fid].rotation)
        close(np.array(fns["fk"](q)).ravel(), data.oMf[fid].translation)
        for ref, fn in frames.items():
            expected = pin.computeFrameJacobian(
                model, data, q, fid, getattr(pin.ReferenceFrame, ref)
            )
            close(fn(q), expected)
        close(np.array(fns["rnea"](q, v, a)).ravel(), pin.rnea(model, data, q, v, a))
        m = pin.crba(model, data, q)
        close(fns["crba"](q), np.triu(m) + np.triu(m, 1).T)
        close(
            np.array(twin.nonlinear_effects(q, v)).ravel(), pin.nonLinearEffects(model, data, q, v)
        )
        close(np.array(twin.gravity(q)).ravel(), pin.computeGeneralizedGravity(model, data, q))


@pytest.mark.parametrize(("robot", "leg"), CASES)
def test_leg_twin_equals_pinocchio(robot, leg):
    leg_model = load_robot(robot).leg(leg)
    check_against_pinocchio(leg_model.model, leg_model.foot_frame)


@pytest.mark.parametrize(
    ("robot", "frame"), [("hyq", "lh_foot"), ("solo12", "FR_FOOT"), ("scalf", "LF_foot")]
)
def test_whole_robot_tree_twin_equals_pinocchio(robot, frame):
    check_against_pinocchio(load_robot(robot).model, frame)


@pytest.mark.parametrize(("robot", "leg"), CASES[::2])
def test_casadi_derivatives(robot, leg):
    leg_model = load_robot(robot).leg(leg)
    model, twin = leg_model.model, leg_model.symbolic
    q, v, a = (ca.SX.sym(n, 2) for n in "qva")
    pos = twin.frame_position(q, leg_model.foot_frame)
    jac = ca.Function(
        "j", [q], [ca.jacobian(pos, q), twin.frame_jacobian(q, leg_model.foot_frame)[:3, :]]
    )
    tau = twin.rnea(q, v, a)
    dtau = ca.Function("dtau", [q, v, a], [ca.jacobian(tau, q), ca.jacobian(tau, a)])
    data = model.createData()
    h = 1e-6
    for qn, vn, an in states(model, seed=9):
        auto, analytic = jac(qn)
        close(auto, analytic)  # AD of FK equals the geometric Jacobian
        dq, da = dtau(qn, vn, an)
        m = pin.crba(model, data, qn)
        close(da, np.triu(m) + np.triu(m, 1).T)  # d tau / d qdd = M(q), exactly
        # d tau / dq against central differences of pin.rnea: truncation ~h^2 |d3 tau| ~ 1e-11,
        # round-off ~eps |tau| / h ~ 1e-10 |tau|: tolerance 1e-5 relative to the largest entry
        fd = np.column_stack(
            [
                (
                    pin.rnea(model, data, qn + h * e, vn, an)
                    - pin.rnea(model, data, qn - h * e, vn, an)
                )
                / (2 * h)
                for e in np.eye(2)
            ]
        )
        np.testing.assert_allclose(np.array(dq), fd, rtol=0, atol=1e-5 * max(1.0, np.abs(fd).max()))


def test_works_on_mx_symbols():
    leg = load_robot("scalf").leg("RF")
    q = ca.MX.sym("q", 2)
    fn = ca.Function("f", [q], [leg.symbolic.rnea(q, ca.DM.zeros(2), ca.DM.zeros(2))])
    np.testing.assert_allclose(
        np.array(fn([0.1, 0.9])).ravel(),
        pin.computeGeneralizedGravity(leg.model, leg.model.createData(), np.array([0.1, 0.9])),
        atol=1e-12,
    )


def test_unsupported_joint_is_named():
    path = load_robot("solo12").urdf_path
    model = pin.buildModelFromUrdf(str(path), pin.JointModelPlanar())
    with pytest.raises(ModelError, match=r"root_joint.*JointModelPlanar"):
        SymbolicChain(model)
