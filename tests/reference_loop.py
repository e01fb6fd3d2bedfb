"""An independent, plain per-sample evaluation of a phase: NumPy and Pinocchio, sample by sample.

This is deliberately *not* scalf-opt's code path: closed-form IK, cylinder geometry and friction are
written here again from the paper's numbers, and the dynamics come straight from ``pin.rnea`` and
``pin.computeFrameJacobian``. The tests compare the compiled CasADi evaluator with it, and
``benchmarks/bench_energy.py`` times both.
"""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

# Table 2 and decision 7, front-leg convention; hind legs negate the joint angle.
CYLINDERS = {
    "hip": (0.28926, 0.05687, math.radians(90 - 5.36 - 54.90), -1),
    "knee": (0.28926, 0.05689, -math.radians(8.02 - 2.35), 1),
}
FRICTION = {1: (220.0, 50.0, 30.0, 0.015), -1: (180.0, 50.0, 20.0, 0.007)}  # B, Fs, Fc, vs
L1, L2 = 0.45099, 0.40487


def ik(leg, p):
    """Closed-form planar IK: both axes +y, leg hanging along -z at zero (SCalf geometry)."""
    x, z = p
    c = (x * x + z * z - L1 * L1 - L2 * L2) / (2 * L1 * L2)
    knee_sign = 1.0 if leg.upper_limits_rad[1] > 0 else -1.0
    q2 = knee_sign * math.acos(c)
    # foot = (-L1 sin q1 - L2 sin(q1 + q2), -L1 cos q1 - L2 cos(q1 + q2))
    k1, k2 = L1 + L2 * math.cos(q2), L2 * math.sin(q2)
    q1 = math.atan2(-x, -z) - math.atan2(k2, k1)
    return np.array([q1, q2])


def heat(v):
    b, fs, fc, vs = FRICTION[1 if v > 0 else -1]
    force = math.copysign(fc + (fs - fc) * math.exp(-abs(v) / vs), v) + b * v if v != 0 else 0.0
    return abs(force * v)


def phase_energy(leg, p, pd, pdd, grf, tau_s):
    """Energy per joint [J] of one phase; also returns the per-sample torques (2, n)."""
    model, data = leg.model, leg.model.createData()
    fid = leg.foot_frame_id
    sign = -1 if leg.is_hind else 1
    n = p.shape[1]
    power = np.zeros((2, n))
    torques = np.zeros((2, n))
    for j in range(n):
        q = ik(leg, p[:, j])
        jac = pin.computeFrameJacobian(model, data, q, fid, pin.LOCAL_WORLD_ALIGNED)[[0, 2]]
        qd = np.linalg.solve(jac, pd[:, j])
        pin.forwardKinematics(model, data, q, qd, np.zeros(2))
        jdot_qd = pin.getFrameClassicalAcceleration(model, data, fid, pin.LOCAL_WORLD_ALIGNED)
        qdd = np.linalg.solve(jac, pdd[:, j] - jdot_qd.linear[[0, 2]])
        tau = pin.rnea(model, data, q, qd, qdd) - jac.T @ grf[:, j]
        torques[:, j] = tau
        for i, name in enumerate(("hip", "knee")):
            a, b, offset, s = CYLINDERS[name]
            phi = offset + s * sign * q[i]
            length = math.sqrt(a * a + b * b - 2 * a * b * math.cos(phi))
            v = s * sign * a * b * math.sin(phi) / length * qd[i]
            power[i, j] = abs(tau[i] * qd[i]) + heat(v)
    h = np.diff(tau_s)
    weights = np.zeros(n)
    weights[:-1] += h / 2
    weights[1:] += h / 2
    return power @ weights, torques
