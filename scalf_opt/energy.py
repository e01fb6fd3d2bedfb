"""The energy pipeline of one leg, built once as CasADi expressions.

Per sample (decisions 7-10), with ``F`` the ground reaction force on the foot in the leg frame
(zero in swing)::

    tau   = RNEA(q, qd, qdd) - J(q)^T F                      joint torques [N m]
    l_i   = sqrt(a^2 + b^2 - 2 a b cos(phi_i(q_i)))           cylinder length [m]
    v_i   = (dl_i/dq_i) qd_i                                  cylinder velocity [m/s]
    f_i   = tau_i / (dl_i/dq_i)                               cylinder force [N]
    P_i   = |tau_i qd_i| + |F_f(v_i) v_i|                     joint power [W] (Eq. 48)

and the energy of a phase is the trapezoidal integral of ``P_i`` over its samples. The same
per-sample :class:`casadi.Function` serves the numeric evaluator (mapped over the samples) and the
NLP (called on symbolic paths), so the physics exists once.

Power accountings (decision 9): ``paper`` (default) ``|tau qd|``; ``positive`` ``max(tau qd, 0)``
(negative work costs nothing); ``regenerative`` ``tau qd`` (negative work is recovered). The
friction heat is added in every accounting.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import cached_property

import casadi as ca
import numpy as np

from scalf_opt.actuators import (
    cylinder_length,
    cylinder_length_rate,
    friction_force,
    friction_heat_rate,
    smooth_max,
)
from scalf_opt.errors import ConfigError
from scalf_opt.kinematics import LegKinematics
from scalf_opt.robot import Leg
from scalf_opt.typing import Expr

ACCOUNTINGS = ("paper", "positive", "regenerative")

SAMPLE_OUTPUTS = (
    "q",
    "qd",
    "qdd",
    "foot",
    "tau",
    "cyl_len",
    "cyl_vel",
    "cyl_force",
    "friction",
    "p_mech",
    "p_heat",
    "power",
)
"""Outputs of the per-sample function, each a 2-vector (joint order hip, knee; foot: x, z)."""


def mechanical_power(
    signed_power_w: Expr, accounting: str, abs_fn: Callable[[Expr], Expr] = ca.fabs
) -> Expr:
    """Mechanical power drawn for a signed joint power ``tau * qd`` [W] under ``accounting``."""
    if accounting == "paper":
        return abs_fn(signed_power_w)
    if accounting == "positive":
        return ca.fmax(signed_power_w, 0)
    if accounting == "regenerative":
        return signed_power_w
    raise ConfigError(f"unknown power accounting {accounting!r}: use {', '.join(ACCOUNTINGS)}")


def trapezoid_weights(tau_s: np.ndarray) -> np.ndarray:
    """Trapezoidal quadrature weights of a sample grid, shape (n,) [s]."""
    tau = np.asarray(tau_s, dtype=float)
    w = np.zeros_like(tau)
    h = np.diff(tau)
    w[:-1] += 0.5 * h
    w[1:] += 0.5 * h
    return w


class LegPhysics:
    """Per-sample physics of one leg as CasADi expressions and compiled functions."""

    def __init__(self, leg: Leg) -> None:
        self.leg = leg
        self.kin = LegKinematics(leg)

    def sample_expr(
        self,
        q: Expr,
        qd: Expr,
        qdd: Expr,
        grf: Expr,
        accounting: str = "paper",
        heat_eps: float | None = None,
    ) -> dict[str, Expr]:
        """Every per-sample quantity for joint motion ``(q, qd, qdd)`` and foot force ``grf``.

        Args:
            q: Joint angles (2x1) [rad].
            qd: Joint rates (2x1) [rad/s].
            qdd: Joint accelerations (2x1) [rad/s^2].
            grf: Ground reaction force on the foot (F_x, F_z) in the leg frame [N].
            accounting: Power accounting for ``power`` (see module docstring).
            heat_eps: ``None`` for the exact friction heat; a velocity [m/s] to replace
                ``max(v, 0)`` by the smooth ``(v + sqrt(v^2 + eps^2)) / 2`` (for the NLP).
        """
        leg = self.leg
        jac = self.kin.jacobian_expr(q)
        tau = leg.symbolic.rnea(q, qd, qdd) - ca.mtimes(jac.T, grf)
        max_fn: Callable[[Expr, Expr], Expr] = (
            ca.fmax if heat_eps is None else (lambda x, _zero: smooth_max(x, heat_eps))
        )
        cols: dict[str, list[Expr]] = {k: [] for k in ("len", "vel", "force", "fric", "heat")}
        nan = ca.SX(float("nan"))
        for i, cyl in enumerate(leg.cylinders):
            if cyl is None:  # ideal actuator: no cylinder, no friction
                cols["len"].append(nan)
                cols["vel"].append(nan)
                cols["force"].append(nan)
                cols["fric"].append(ca.SX(0.0))
                cols["heat"].append(ca.SX(0.0))
                continue
            rate = cylinder_length_rate(cyl, q[i])
            vel = rate * qd[i]
            cols["len"].append(cylinder_length(cyl, q[i]))
            cols["vel"].append(vel)
            cols["force"].append(tau[i] / rate)
            cols["fric"].append(friction_force(cyl.friction, vel))
            cols["heat"].append(friction_heat_rate(cyl.friction, vel, max_fn))
        p_mech = tau * qd
        p_heat = ca.vertcat(*cols["heat"])
        power = mechanical_power(p_mech, accounting) + p_heat
        return {
            "q": q,
            "qd": qd,
            "qdd": qdd,
            "foot": self.kin.forward_expr(q),
            "tau": tau,
            "cyl_len": ca.vertcat(*cols["len"]),
            "cyl_vel": ca.vertcat(*cols["vel"]),
            "cyl_force": ca.vertcat(*cols["force"]),
            "friction": ca.vertcat(*cols["fric"]),
            "p_mech": p_mech,
            "p_heat": p_heat,
            "power": power,
        }

    def sample_function(
        self, space: str, accounting: str = "paper", heat_eps: float | None = None
    ) -> ca.Function:
        """Compiled per-sample function ``(y, yd, ydd, grf) -> SAMPLE_OUTPUTS``.

        ``space == "joint"``: ``y`` are joint angles; ``"foot"``: foot positions in the leg frame,
        mapped to joint motion by closed-form IK and the Jacobian.
        """
        key = (space, accounting, heat_eps)
        cache = self._functions
        if key not in cache:
            y, yd, ydd, grf = (ca.SX.sym(n, 2) for n in ("y", "yd", "ydd", "grf"))
            if space == "foot":
                q, qd, qdd = self.kin.joint_motion_expr(y, yd, ydd)
            elif space == "joint":
                q, qd, qdd = y, yd, ydd
            else:
                raise ConfigError(f"space must be 'foot' or 'joint', got {space!r}")
            out = self.sample_expr(q, qd, qdd, grf, accounting, heat_eps)
            cache[key] = ca.Function(
                f"{self.leg.name}_{space}_sample",
                [y, yd, ydd, grf],
                [out[k] for k in SAMPLE_OUTPUTS],
                ["y", "yd", "ydd", "grf"],
                list(SAMPLE_OUTPUTS),
            )
        return cache[key]

    @cached_property
    def _functions(self) -> dict[tuple[str, str, float | None], ca.Function]:
        return {}


@dataclass(frozen=True)
class PhaseResult:
    """Every sample of one phase of one leg (numeric), plus its energy per joint.

    Array shapes: (2, n) with rows (hip, knee), or (x, z) for ``foot`` and ``grf``.

    Attributes:
        leg: Leg name.
        phase: ``stance`` or ``swing``.
        t_s: Cycle time of each sample [s], shape (n,).
        tau_s: Time since the phase began [s], shape (n,).
        values: Arrays by name: SAMPLE_OUTPUTS plus ``grf`` [SI units].
        energy_j: Energy per joint over the phase [J], shape (2,).
        heat_j: Friction-heat part of ``energy_j`` [J], shape (2,).
    """

    leg: str
    phase: str
    t_s: np.ndarray
    tau_s: np.ndarray
    values: dict[str, np.ndarray]
    energy_j: np.ndarray
    heat_j: np.ndarray


def evaluate_phase(
    physics: LegPhysics,
    space: str,
    samples: np.ndarray,
    grf: np.ndarray,
    tau_s: np.ndarray,
    t_offset_s: float,
    period_s: float,
    phase: str,
    accounting: str = "paper",
) -> PhaseResult:
    """Evaluate one phase numerically through the compiled per-sample function.

    Args:
        physics: The leg's physics.
        space: ``foot`` or ``joint``: what ``samples`` hold.
        samples: Path samples, shape (3, 2, n): value, first and second time derivative.
        grf: Ground reaction force on the foot, shape (2, n) [N].
        tau_s: Time since the phase began, shape (n,) [s].
        t_offset_s: Cycle time at which the phase begins [s].
        period_s: Gait period, to wrap cycle times into [0, T) [s].
        phase: ``stance`` or ``swing``.
        accounting: Power accounting.
    """
    n = samples.shape[-1]
    fn = physics.sample_function(space, accounting).map(n)
    out = fn(samples[0], samples[1], samples[2], grf)
    values = {k: np.array(v) for k, v in zip(SAMPLE_OUTPUTS, out, strict=True)}
    values["grf"] = np.asarray(grf, dtype=float)
    w = trapezoid_weights(tau_s)
    t = np.mod(t_offset_s + tau_s, period_s)
    if t.size > 1 and t[-1] < t[-2]:
        t[-1] += period_s  # a phase ending exactly at the cycle's end stays at T, not at 0
    return PhaseResult(
        leg=physics.leg.name,
        phase=phase,
        t_s=t,
        tau_s=np.asarray(tau_s, dtype=float),
        values=values,
        energy_j=values["power"] @ w,
        heat_j=values["p_heat"] @ w,
    )
