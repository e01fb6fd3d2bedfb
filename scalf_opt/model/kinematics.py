r"""Sagittal kinematics of a leg: closed-form IK, foot Jacobian and its time derivative.

Every formula is written once as a CasADi expression; numeric calls evaluate compiled
``casadi.Function`` objects (mapped over samples). Foot positions are ``(x, z)`` in the leg
frame (origin at the pitching hip, trunk axes) [m]; joint vectors are ``(hip pitch, knee)`` [rad].
Arrays of samples have shape ``(2, n_samples)``.

Inverse kinematics. Write a sagittal vector ``(x, z)`` as the complex number ``w = z + i x``; a
rotation by ``a`` about +y multiplies it by ``exp(i a)``. With ``k0`` (hip to knee) and ``f0``
(knee to foot) at q = 0 and axis signs ``s1, s2``:

.. math::

    w_p = e^{i s_1 q_1} (w_{k0} + e^{i s_2 q_2} w_{f0}), \\qquad
    \\cos\\beta = \\frac{|p|^2 - l_1^2 - l_2^2}{2 l_1 l_2}, \\quad
    \\beta = s_2 q_2 + \\arg w_{f0} - \\arg w_{k0},

so ``q2 = s2 (b acos(c) - arg f0 + arg k0)`` on knee branch ``b = +-1`` and
``s1 q1 = arg(w_p / w_v)`` with ``v = k0 + R_y(s2 q2) f0``. The knee branch and the 2-pi shifts
are chosen once per leg (:attr:`LegKinematics.branch`): those that give back the leg's reference
posture (the robot's standing posture, else the middle of the joint ranges) from its own foot
position, so that IK inverts FK around that posture and the map from foot position to joint
angles is smooth.

Joint rates follow from the Jacobian: ``qd = J^-1 pd`` and ``qdd = J^-1 (pdd - Jdot qd)``.
"""

from __future__ import annotations

import math
from functools import cached_property
from typing import NamedTuple

import casadi as ca
import numpy as np

from scalf_opt.errors import InfeasibleError, ModelError
from scalf_opt.model.leg import Leg
from scalf_opt.types import Expr

REACH_TOLERANCE = 1e-12
"""Slack on |cos(beta)| <= 1 before a target counts as unreachable (round-off of exact targets)."""

BRANCH_MATCH_TOLERANCE_RAD = 1e-6
"""How close the IK of the mid-range posture must come back to it for a knee branch to count."""


class IkBranch(NamedTuple):
    """Knee branch (+1 or -1) and the 2-pi shifts added to the hip and knee angles [rad]."""

    knee: int
    shift_hip_rad: float
    shift_knee_rad: float


class LegKinematics:
    """Kinematics of one :class:`~scalf_opt.model.leg.Leg`: CasADi expressions, numeric calls."""

    def __init__(self, leg: Leg) -> None:
        self.leg = leg

    # --- expressions (SX, MX or DM in; same type out) -------------------------------------------
    def forward_expr(self, q: Expr) -> Expr:
        """Foot position ``(x, z)`` in the leg frame for joint angles ``q`` (2x1) [m]."""
        p = self.leg.symbolic.frame_position(q, self.leg.foot_frame)
        hip = self.leg.hip_origin_m
        return ca.vertcat(p[0] - hip[0], p[2] - hip[2])

    def jacobian_expr(self, q: Expr) -> Expr:
        """Sagittal foot Jacobian d(x, z)/dq (2x2) [m/rad], Pinocchio's LOCAL_WORLD_ALIGNED rows."""
        jac = self.leg.symbolic.frame_jacobian(q, self.leg.foot_frame, "LOCAL_WORLD_ALIGNED")
        return ca.vertcat(jac[0, :], jac[2, :])

    def jacobian_dot_expr(self, q: Expr, qd: Expr) -> Expr:
        """Time derivative of the Jacobian along ``qd`` (2x2) [m/(rad s)]: sum_j dJ/dq_j qd_j."""
        return self._jacobian_dot_fn(q, qd)

    @cached_property
    def _jacobian_dot_fn(self) -> ca.Function:
        # jtimes differentiates with respect to a purely symbolic q, so build it on symbols once
        q, qd = ca.SX.sym("q", 2), ca.SX.sym("qd", 2)
        jac = self.jacobian_expr(q)
        jdot = ca.horzcat(*[ca.jtimes(jac[:, j], q, qd) for j in range(2)])
        return ca.Function("jacobian_dot", [q, qd], [jdot])

    def inverse_expr(self, p: Expr, branch: IkBranch | None = None) -> Expr:
        """Closed-form inverse kinematics (2x1) [rad] on the leg's fixed knee branch.

        Outside the reach the result is NaN (``acos`` of a number beyond +-1); use
        :meth:`reach_cosine_expr` to constrain or check reachability.

        Args:
            p: Foot position (x, z) in the leg frame [m].
            branch: Knee branch and shifts; default :attr:`branch` (the leg's own).
        """
        leg = self.leg
        k0, f0 = leg.thigh_vector_m, leg.shank_vector_m
        s1, s2 = leg.axis_signs
        knee, shift_hip, shift_knee = branch if branch is not None else self.branch
        psi_k = math.atan2(k0[0], k0[1])
        psi_f = math.atan2(f0[0], f0[1])
        knee_rel = knee * ca.acos(self.reach_cosine_expr(p)) - psi_f + psi_k  # = s2 * q2
        c, s = ca.cos(knee_rel), ca.sin(knee_rel)
        vx = k0[0] + c * f0[0] + s * f0[1]
        vz = k0[1] - s * f0[0] + c * f0[1]
        hip_rel = ca.atan2(p[0] * vz - p[1] * vx, p[0] * vx + p[1] * vz)  # = s1 * q1
        return ca.vertcat(s1 * hip_rel + shift_hip, s2 * knee_rel + shift_knee)

    @cached_property
    def branch(self) -> IkBranch:
        """The knee branch and 2-pi shifts that invert FK at the leg's reference posture.

        Raises:
            ModelError: Neither branch gives the posture back (its knee is straight, a
                singular posture, or it is not finite).
        """
        q_mid = self.leg.reference_posture_rad
        if not np.all(np.isfinite(q_mid)):
            raise ModelError(
                f"{self.leg.source}: leg {self.leg.name} needs finite joint limits or a "
                f"reference posture (got {q_mid} rad)"
            )
        p_mid = ca.DM(self.forward_expr(ca.DM(q_mid)))
        for knee in (1, -1):
            raw = np.array(ca.evalf(self.inverse_expr(p_mid, IkBranch(knee, 0.0, 0.0))))
            shifts = 2 * math.pi * np.round((q_mid - raw.ravel()) / (2 * math.pi))
            if np.all(np.abs(raw.ravel() + shifts - q_mid) < BRANCH_MATCH_TOLERANCE_RAD):
                return IkBranch(knee, float(shifts[0]), float(shifts[1]))
        raise ModelError(
            f"{self.leg.source}: leg {self.leg.name}: no knee branch of the closed-form IK "
            f"returns the reference posture q = {q_mid} rad (a straight knee is singular)"
        )

    def reach_cosine_expr(self, p: Expr) -> Expr:
        """Cosine of the knee's interior angle; the target is reachable iff it lies in [-1, 1]."""
        l1, l2 = self.leg.thigh_length_m, self.leg.shank_length_m
        return (p[0] ** 2 + p[1] ** 2 - l1**2 - l2**2) / (2 * l1 * l2)

    def joint_motion_expr(self, p: Expr, pd: Expr, pdd: Expr) -> tuple[Expr, Expr, Expr]:
        """Joint angles, rates and accelerations for a foot position, velocity and acceleration."""
        q = self.inverse_expr(p)
        jac = self.jacobian_expr(q)
        qd = ca.solve(jac, pd)
        qdd = ca.solve(jac, pdd - ca.mtimes(self.jacobian_dot_expr(q, qd), qd))
        return q, qd, qdd

    # --- compiled functions -------------------------------------------------------------------
    @cached_property
    def functions(self) -> dict[str, ca.Function]:
        """Compiled per-sample functions.

        Names: ``fk``, ``ik``, ``reach``, ``jacobian``, ``jacobian_dot``, ``motion``.
        """
        q, qd = ca.SX.sym("q", 2), ca.SX.sym("qd", 2)
        p, pd, pdd = ca.SX.sym("p", 2), ca.SX.sym("pd", 2), ca.SX.sym("pdd", 2)
        motion = self.joint_motion_expr(p, pd, pdd)
        return {
            "fk": ca.Function("fk", [q], [self.forward_expr(q)], ["q"], ["p"]),
            "ik": ca.Function("ik", [p], [self.inverse_expr(p)], ["p"], ["q"]),
            "reach": ca.Function("reach", [p], [self.reach_cosine_expr(p)], ["p"], ["c"]),
            "jacobian": ca.Function("jacobian", [q], [self.jacobian_expr(q)], ["q"], ["J"]),
            "jacobian_dot": ca.Function(
                "jacobian_dot", [q, qd], [self.jacobian_dot_expr(q, qd)], ["q", "qd"], ["Jdot"]
            ),
            "motion": ca.Function(
                "motion", [p, pd, pdd], list(motion), ["p", "pd", "pdd"], ["q", "qd", "qdd"]
            ),
        }

    def _mapped(self, name: str, *args: np.ndarray) -> list[np.ndarray]:
        arrays = [np.atleast_2d(np.asarray(a, dtype=float).reshape(2, -1)) for a in args]
        fn = self.functions[name].map(arrays[0].shape[1])
        out = fn(*arrays)
        out = out if isinstance(out, tuple) else (out,)
        return [np.array(o) for o in out]

    # --- numeric API --------------------------------------------------------------------------
    def forward(self, q: np.ndarray) -> np.ndarray:
        """Foot positions (2, n) [m] for joint angles (2, n) [rad]; a (2,) input gives (2,)."""
        out = self._mapped("fk", q)[0]
        return out.reshape(np.shape(q))

    def check_reachable(self, p: np.ndarray) -> None:
        """Raise :class:`InfeasibleError` naming the first target outside the leg's reach."""
        c = self._mapped("reach", p)[0].ravel()
        bad = np.flatnonzero(~(np.abs(c) <= 1.0 + REACH_TOLERANCE))
        if bad.size:
            target = np.asarray(p, dtype=float).reshape(2, -1)[:, bad[0]]
            lo, hi = self.leg.reach_m
            dist = float(np.hypot(*target))
            raise InfeasibleError(
                f"leg {self.leg.name}: foot target (x={target[0]:.4f} m, z={target[1]:.4f} m) is "
                f"{dist:.4f} m from the hip, outside the reach [{lo:.4f}, {hi:.4f}] m"
            )

    def inverse(self, p: np.ndarray) -> np.ndarray:
        """Joint angles (2, n) [rad] for foot targets (2, n) [m]; raises if one is unreachable."""
        self.check_reachable(p)
        p_clipped = np.asarray(p, dtype=float)
        return self._mapped("ik", p_clipped)[0].reshape(np.shape(p))

    def jacobian(self, q: np.ndarray) -> np.ndarray:
        """Foot Jacobian (2, 2) [m/rad] at one configuration ``q`` (2,)."""
        return np.array(self.functions["jacobian"](np.asarray(q, dtype=float)))

    def jacobian_dot(self, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """Jacobian time derivative (2, 2) at ``q`` (2,) moving with ``qd`` (2,)."""
        return np.array(
            self.functions["jacobian_dot"](np.asarray(q, dtype=float), np.asarray(qd, dtype=float))
        )

    def joint_motion(
        self, p: np.ndarray, pd: np.ndarray, pdd: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Joint angles, rates, accelerations (each (2, n)) from foot samples (each (2, n))."""
        self.check_reachable(p)
        q, qd, qdd = self._mapped("motion", p, pd, pdd)
        return q, qd, qdd
