"""The energy pipeline of one leg, built once as CasADi expressions.

Per sample (decisions 7-10), with ``F`` the ground reaction force on the foot in the leg frame
(zero in swing)::

    tau   = RNEA(q, qd, qdd) - J(q)^T F                      joint torques [N m]
    P_i   = A(tau_i qd_i) + L_i(q_i, qd_i, tau_i)            power drawn by joint i [W]

where ``A`` is the power accounting (applied when the joint's drive charges its mechanical power)
and ``L_i`` the drive's loss rate (for SCalf's cylinders the Stribeck friction heat, so that
``P_i = |tau_i qd_i| + |F_f(v_i) v_i|``, Eq. 48). The drive adds its own outputs (a cylinder's
length, velocity, force, friction). The energy of a phase is the trapezoidal integral of ``P_i``
over its samples. The same per-sample :class:`casadi.Function` serves the numeric evaluator
(mapped over the samples) and the NLP (called on symbolic paths), so the physics exists once.

Power accountings (decision 9): ``paper`` (default) ``|tau qd|``; ``positive`` ``max(tau qd, 0)``
(negative work costs nothing); ``regenerative`` ``tau qd`` (negative work is recovered).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import casadi as ca
import numpy as np

from scalf_opt.actuators.drive import Channel, Drive, MaxFn
from scalf_opt.actuators.stribeck import smooth_max
from scalf_opt.energy.accounting import accounting as power_accounting
from scalf_opt.energy.built_once import BuiltOnce
from scalf_opt.model.kinematics import LegKinematics
from scalf_opt.types import JOINT_ROLES, Accounting, Expr, Space, casadi_name, check_choice

CORE_OUTPUTS: tuple[str, ...] = ("q", "qd", "qdd", "foot", "tau", "p_mech", "p_loss", "power")
"""Outputs every leg has, each a 2-vector: joint order (hip, knee), foot (x, z). ``p_mech`` is the
signed joint power ``tau qd``, ``p_loss`` the drives' loss rate, ``power`` what is charged [W]."""


def mechanical_power(
    signed_power_w: Expr, accounting: Accounting, abs_fn: Callable[[Expr], Expr] | None = None
) -> Expr:
    """Mechanical power drawn for a signed joint power ``tau * qd`` [W] under ``accounting``."""
    return power_accounting(accounting).charge(signed_power_w, abs_fn)


def trapezoid_weights(t_s: np.ndarray) -> np.ndarray:
    """Trapezoidal quadrature weights of a sample grid, shape (n,) [s]."""
    t = np.asarray(t_s, dtype=float)
    w = np.zeros_like(t)
    h = np.diff(t)
    w[:-1] += 0.5 * h
    w[1:] += 0.5 * h
    return w


@dataclass(frozen=True)
class DriveOutput:
    """One drive output of a leg: ``<channel>_<joint role>``, e.g. ``cyl_len_hip``.

    Attributes:
        joint: 0 (hip pitch) or 1 (knee).
        channel: The drive's channel.
    """

    joint: int
    channel: Channel

    @property
    def name(self) -> str:
        """Output name, e.g. ``cyl_len_hip``."""
        return f"{self.channel.name}_{JOINT_ROLES[self.joint]}"

    @property
    def column(self) -> str:
        """Column name with its unit, e.g. ``cyl_len_hip_m``."""
        return f"{self.name}_{self.channel.unit}"


class LegPhysics:
    """Per-sample physics of one leg over its two drives, as CasADi expressions and functions.

    Args:
        kinematics: The leg's kinematics (and through it the leg and its CasADi twin).
        drives: The (hip pitch, knee) drives.
    """

    def __init__(self, kinematics: LegKinematics, drives: tuple[Drive, Drive]) -> None:
        self.kin = kinematics
        self.leg = kinematics.leg
        self.drives = drives
        self.built = BuiltOnce()
        """What the optimizers build from this leg once (kernels, bound analyses, NLPs)."""

    @cached_property
    def drive_outputs(self) -> tuple[DriveOutput, ...]:
        """The drives' outputs, channel by channel, hip before knee (the CSV's column order)."""
        out: list[DriveOutput] = []
        for channel in dict.fromkeys(c for d in self.drives for c in d.channels):
            out += [
                DriveOutput(i, channel) for i, d in enumerate(self.drives) if channel in d.channels
            ]
        return tuple(out)

    @property
    def output_names(self) -> tuple[str, ...]:
        """Names of the per-sample function's outputs: core ones, then the drives'."""
        return CORE_OUTPUTS + tuple(o.name for o in self.drive_outputs)

    def sample_expr(
        self,
        q: Expr,
        qd: Expr,
        qdd: Expr,
        grf: Expr,
        accounting: Accounting = "paper",
        heat_eps: float | None = None,
    ) -> dict[str, Expr]:
        """Every per-sample quantity for joint motion ``(q, qd, qdd)`` and foot force ``grf``.

        Args:
            q: Joint angles (2x1) [rad].
            qd: Joint rates (2x1) [rad/s].
            qdd: Joint accelerations (2x1) [rad/s^2].
            grf: Ground reaction force on the foot (F_x, F_z) in the leg frame [N].
            accounting: Power accounting for ``power`` (see module docstring).
            heat_eps: ``None`` for the exact drive losses; a velocity [m/s] to replace their
                ``max(v, 0)`` by the smooth ``(v + sqrt(v^2 + eps^2)) / 2`` (for the NLP).
        """
        jac = self.kin.jacobian_expr(q)
        tau = self.leg.symbolic.rnea(q, qd, qdd) - ca.mtimes(jac.T, grf)
        power, p_loss = self.power_expr(q, qd, tau, accounting, heat_eps)
        extra = {}
        for i, drive in enumerate(self.drives):
            for name, value in drive.outputs(q[i], qd[i], tau[i]).items():
                extra[f"{name}_{JOINT_ROLES[i]}"] = value
        return {
            "q": q,
            "qd": qd,
            "qdd": qdd,
            "foot": self.kin.forward_expr(q),
            "tau": tau,
            "p_mech": tau * qd,
            "p_loss": p_loss,
            "power": power,
            **{o.name: extra[o.name] for o in self.drive_outputs},
        }

    def power_expr(
        self,
        q: Expr,
        qd: Expr,
        tau: Expr,
        accounting: Accounting = "paper",
        heat_eps: float | None = None,
    ) -> tuple[Expr, Expr]:
        """Power drawn by the two joints for any joint motion and torque (2x1 each) [W].

        Returns ``(power, p_loss)``: the charged mechanical power plus the drives' losses, and
        the losses alone. Every power in scalf-opt comes from here: the planned samples, and
        torques and rates that were measured or simulated.
        """
        max_fn: MaxFn = ca.fmax if heat_eps is None else (lambda x, _: smooth_max(x, heat_eps))
        losses, charged = [], []
        for i, drive in enumerate(self.drives):
            losses.append(drive.loss_rate(q[i], qd[i], tau[i], max_fn))
            mech = mechanical_power(tau[i] * qd[i], accounting)
            charged.append(mech if drive.charges_joint_power else 0.0 * mech)
        p_loss = ca.vertcat(*losses)
        return ca.vertcat(*charged) + p_loss, p_loss

    def power_function(self, accounting: Accounting = "paper") -> ca.Function:
        """``(q, qd, tau) -> (power, p_loss)`` per sample, 2x1 each [W] (:meth:`power_expr`).

        Map it over samples (``.map(n)``) to charge measured or simulated joint motion.
        """
        key = ("power", accounting, None)
        if key not in self._functions:
            q, qd, tau = (ca.SX.sym(n, 2) for n in ("q", "qd", "tau"))
            power, p_loss = self.power_expr(q, qd, tau, accounting)
            self._functions[key] = ca.Function(
                casadi_name(self.leg.name, "power"),
                [q, qd, tau],
                [power, p_loss],
                ["q", "qd", "tau"],
                ["power", "p_loss"],
            )
        return self._functions[key]

    def sample_function(
        self, space: Space, accounting: Accounting = "paper", heat_eps: float | None = None
    ) -> ca.Function:
        """Compiled per-sample function ``(y, yd, ydd, grf) -> output_names``.

        ``space == "joint"``: ``y`` are joint angles; ``"foot"``: foot positions in the leg frame,
        mapped to joint motion by closed-form IK and the Jacobian.
        """
        check_choice(space, Space, "space")
        key = (space, accounting, heat_eps)
        if key not in self._functions:
            y, yd, ydd, grf = (ca.SX.sym(n, 2) for n in ("y", "yd", "ydd", "grf"))
            if space == "foot":
                q, qd, qdd = self.kin.joint_motion_expr(y, yd, ydd)
            else:
                q, qd, qdd = y, yd, ydd
            out = self.sample_expr(q, qd, qdd, grf, accounting, heat_eps)
            self._functions[key] = ca.Function(
                casadi_name(self.leg.name, space, "sample"),
                [y, yd, ydd, grf],
                [out[k] for k in self.output_names],
                ["y", "yd", "ydd", "grf"],
                list(self.output_names),
            )
        return self._functions[key]

    def wrench_function(self, space: Space) -> ca.Function:
        """``(y, yd, ydd) -> wrench (6)``: the leg's part of the load on the stance feet.

        The spatial force the trunk supplies to the leg's moving links (thigh, shank, foot) for
        their motion and weight, in the trunk frame about its origin, force [N] then moment
        [N m] (:meth:`~scalf_opt.model.symbolic.SymbolicChain.root_wrench`). It depends on this
        leg's motion only, so the whole robot's load is a sum of one such term per leg and a
        constant one for the trunk (:mod:`scalf_opt.energy.loads`).
        """
        check_choice(space, Space, "space")
        key = (space, "wrench", None)
        if key not in self._functions:
            y, yd, ydd = (ca.SX.sym(n, 2) for n in ("y", "yd", "ydd"))
            if space == "foot":
                q, qd, qdd = self.kin.joint_motion_expr(y, yd, ydd)
            else:
                q, qd, qdd = y, yd, ydd
            self._functions[key] = ca.Function(
                casadi_name(self.leg.name, space, "wrench"),
                [y, yd, ydd],
                [self.leg.symbolic.root_wrench(q, qd, qdd)],
                ["y", "yd", "ydd"],
                ["wrench"],
            )
        return self._functions[key]

    @cached_property
    def _functions(self) -> dict[tuple[str, str, float | None], ca.Function]:
        return {}
