"""The per-sample functions the swing optimizers evaluate: one leg's physics at one sample.

A *kernel* maps one swing sample ``y = (y, y', y'')`` (6 numbers: value, rate and acceleration
of the two coordinates of the family's space) to what the optimization needs at that sample:

``exact``
    ``(power (2), p_mech (2), c (m))``: the charged power of each joint under the accounting (the
    exact, non-smooth energy integrand), the signed joint power ``tau qd``, and the constraint
    quantities ``c``;
``smooth``
    ``(p_mech (2), p_loss (1), c (m))`` for the NLP: the drives' losses with the smooth max
    (:data:`HEAT_SMOOTHING_EPS_M_S`), summed over the joints.

The constraint quantities, in :attr:`Kernel.rows` order: every bound of the leg
(:func:`~scalf_opt.energy.limits.leg_bounds`: joint range, URDF velocity and effort limits,
drive bounds), the foot height ``z``, its vertical velocity ``z'`` and acceleration ``z''``
and, in foot space, the reach cosine of the IK (reachable iff in [-1, 1]).

Every expression comes from :class:`~scalf_opt.energy.physics.LegPhysics` and
:class:`~scalf_opt.model.kinematics.LegKinematics`: no physics is written here. A kernel depends
only on the leg, its drives, the space and the accounting, never on the gait or the family, so
it is built and compiled once per leg (:func:`~scalf_opt.energy.codegen.compile_library`, cached
on disk; CasADi's virtual machine without a compiler) and serves every problem of that leg.
The NLP's kernel is compiled with its first and second derivatives, so the NLP maps it over the
samples and CasADi differentiates through it.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field
from functools import cached_property

import casadi as ca
import numpy as np

from scalf_opt.energy.built_once import BuiltOnce
from scalf_opt.energy.codegen import compile_library, load_external
from scalf_opt.energy.limits import Bound, leg_bounds
from scalf_opt.energy.physics import LegPhysics
from scalf_opt.types import Accounting, Space, casadi_name

SYMBOLIC_LOCK = threading.RLock()
"""Held while a CasADi graph is built (kernels, NLPs). CasADi's symbolic core is not thread-safe
and its Python calls release the GIL, so two legs solved on parallel threads must not build at
once: a test run crashed with a segmentation fault in ``Function.jacobian`` on one leg's thread
beside a ``reshape`` on the other's. Only the builds wait; the solves still overlap."""

HEAT_SMOOTHING_EPS_M_S = 1e-4
"""Velocity scale of the smooth max in the NLP's drive losses [m/s].

It is 70x below the smaller Stribeck velocity (0.007 m/s); the smooth max overestimates
``max(v, 0)`` by at most eps/2, so the heat rate changes by at most ``F_s eps / 2 = 2.5 mW`` per
cylinder: far below the energies compared (the exact energy is what every report prints).
"""

FOOT_Z = "foot_z"
FOOT_Z_VEL = "foot_z_vel"
FOOT_Z_ACCEL = "foot_z_accel"
REACH = "reach"


@dataclass
class Kernel:
    """The per-sample functions of one leg in one space.

    Attributes:
        physics: The leg's physics.
        space: ``joint`` or ``foot``: what the sample's coordinates are.
        bounds: The leg's bounds; the first rows of ``c``.
        rows: Names of the rows of ``c``: each bound's name, then ``foot_z``, ``foot_z_vel``,
            ``foot_z_accel`` and (foot space) ``reach``.
        compiled: The functions run as native code (else in CasADi's virtual machine).
    """

    physics: LegPhysics
    space: Space
    bounds: tuple[Bound, ...]
    rows: tuple[str, ...]
    compiled: bool = False
    _smooth: ca.Function | None = None
    _smooth_hessian: ca.Function | None = None
    _exact: dict[str, ca.Function] = field(default_factory=dict)
    _mapped: dict[tuple[str, int], ca.Function] = field(default_factory=dict)
    nlps: BuiltOnce = field(default_factory=BuiltOnce)
    """Built NLPs by their structure (filled by :mod:`scalf_opt.optimize.nlp`)."""

    def row(self, name: str) -> int:
        """Index of a named row of ``c``."""
        return self.rows.index(name)

    @cached_property
    def _y(self) -> ca.SX:
        """The sample's symbols: value, rate and acceleration of the two coordinates."""
        return ca.SX.sym("y", 6)

    def _expressions(self, accounting: Accounting, heat_eps: float | None) -> dict[str, ca.SX]:
        y = self._y
        fn = self.physics.sample_function(self.space, accounting, heat_eps)
        out = dict(
            zip(
                self.physics.output_names,
                fn(y[0:2], y[2:4], y[4:6], ca.DM.zeros(2, 1)),
                strict=True,
            )
        )
        kin = self.physics.kin
        if self.space == "joint":
            q, qd, qdd = out["q"], out["qd"], out["qdd"]
            jacobian = kin.jacobian_expr(q)
            accel = ca.mtimes(jacobian, qdd) + ca.mtimes(kin.jacobian_dot_expr(q, qd), qd)
            foot_z_vel = ca.mtimes(jacobian, qd)[1]
            foot_z_accel = accel[1]
        else:
            foot_z_vel, foot_z_accel = y[3], y[5]
        c = [b.select(out) for b in self.bounds]
        c += [out["foot"][1], foot_z_vel, foot_z_accel]
        if self.space == "foot":
            c.append(kin.reach_cosine_expr(y[0:2]))
        out["c"] = ca.vertcat(*c)
        return out

    def smooth(self) -> ca.Function:
        """``y (6) -> out (5 + m)``: p_mech (2), summed smooth losses (1), c (m); NLP use."""
        with SYMBOLIC_LOCK:
            if self._smooth is None:
                e = self._expressions("paper", HEAT_SMOOTHING_EPS_M_S)
                name = casadi_name(self.physics.leg.name, self.space, "nlp_sample")
                out = ca.vertcat(e["p_mech"], ca.sum1(e["p_loss"]), e["c"])
                fn = ca.Function(name, [self._y], [out])
                seed = ca.SX.sym("seed", out.numel())
                hessian = ca.Function(
                    f"{name}_hessian", [self._y, seed], [ca.hessian(ca.dot(seed, out), self._y)[0]]
                )
                adjoint = fn.reverse(1)
                library = compile_library(
                    name, [fn, fn.jacobian(), fn.forward(1), adjoint, adjoint.jacobian(), hessian]
                )
                compiled = load_external(name, library)
                self.compiled = self.compiled or compiled is not None
                self._smooth = compiled or fn
                self._smooth_hessian = load_external(hessian.name(), library) or hessian
        return self._smooth

    def smooth_hessian(self) -> ca.Function:
        """``(y (6), seed (5 + m)) -> (6 x 6)``: the Hessian of ``seed' smooth(y)`` in ``y``.

        Compiled on its own: the adjoint's Jacobian that CasADi differentiates ``smooth`` with
        computes two more 6 x (5 + m) blocks beside it, and took three times as long.
        """
        self.smooth()
        assert self._smooth_hessian is not None
        return self._smooth_hessian

    def exact(self, accounting: Accounting) -> ca.Function:
        """``y (6) -> out (4 + m)``: charged power (2), p_mech (2), c (m); exact energy."""
        with SYMBOLIC_LOCK:
            if accounting not in self._exact:
                e = self._expressions(accounting, None)
                name = casadi_name(self.physics.leg.name, self.space, accounting, "exact_sample")
                fn = ca.Function(name, [self._y], [ca.vertcat(e["power"], e["p_mech"], e["c"])])
                compiled = load_external(name, compile_library(name, [fn]))
                self.compiled = self.compiled or compiled is not None
                self._exact[accounting] = compiled or fn
        return self._exact[accounting]

    def evaluate_exact(self, accounting: Accounting, samples: np.ndarray) -> np.ndarray:
        """The exact kernel on every column of ``samples`` (6, n): shape (4 + m, n)."""
        n = samples.shape[1]
        key = (accounting, n)
        if key not in self._mapped:
            self._mapped[key] = self.exact(accounting).map(n)
        return np.array(self._mapped[key](samples))


def kernel_for(physics: LegPhysics, space: Space) -> Kernel:
    """The leg's kernel in ``space``, built once per leg (and compiled once per machine)."""

    def build() -> Kernel:
        bounds = leg_bounds(physics)
        rows = (*(b.name for b in bounds), FOOT_Z, FOOT_Z_VEL, FOOT_Z_ACCEL)
        if space == "foot":
            rows = (*rows, REACH)
        return Kernel(physics, space, bounds, rows)

    with SYMBOLIC_LOCK:
        return physics.built.get(("kernel", space), build)


STANCE_INPUTS = 18
"""Inputs per stance leg and sample of the stance kernel: q (2), qd (2), tau0 (2), gain (12)."""


def stance_kernel(
    varying: tuple[LegPhysics, ...], space: Space, stance: tuple[LegPhysics, ...]
) -> ca.Function:
    """The pair's stance at one sample under whole-body loads, for the NLP (compiled once).

    ``(y (6 m), d (18 k)) -> (p_mech (2 k), loss (1), limited)``: the samples ``y`` of the ``m``
    varying legs in ``space`` (one after the other; their wrenches add), and per stance leg its
    joint angles, rates, fixed torques and the 2 x 6 gain of its torques on the varying legs'
    wrench (row-major); out come the stance joints' signed powers ``tau qd``, their drives'
    summed losses with the smooth max (:data:`HEAT_SMOOTHING_EPS_M_S`) and, per stance leg, the
    bounded quantities the swing moves (:func:`stance_limited_bounds`: torques and
    torque-dependent drive outputs, such as a cylinder's force). See
    :mod:`scalf_opt.energy.coupling`.
    """
    # the first varying leg owns it; the others are named by identity (they live as long)
    key = ("stance kernel", space, tuple(id(v) for v in varying[1:]), tuple(id(s) for s in stance))

    def build() -> ca.Function:
        y = ca.SX.sym("y", 6 * len(varying))
        d = ca.SX.sym("d", STANCE_INPUTS * len(stance))
        wrenches = [
            physics.wrench_function(space)(
                y[6 * i : 6 * i + 2], y[6 * i + 2 : 6 * i + 4], y[6 * i + 4 : 6 * i + 6]
            )
            for i, physics in enumerate(varying)
        ]
        wrench = sum(wrenches[1:], wrenches[0])
        powers, losses, limited = [], [], []
        for k, physics in enumerate(stance):
            block = d[STANCE_INPUTS * k : STANCE_INPUTS * (k + 1)]
            q, qd, tau0 = block[0:2], block[2:4], block[4:6]
            gain = ca.reshape(block[6:18], 6, 2).T  # row-major 2 x 6
            tau = tau0 + ca.mtimes(gain, wrench)
            powers.append(tau * qd)
            _, loss = physics.power_expr(q, qd, tau, heat_eps=HEAT_SMOOTHING_EPS_M_S)
            losses.append(ca.sum1(loss))
            limited.append(stance_limit_function(physics)(q, qd, tau))
        names = [*(v.leg.name for v in varying), space, *(s.leg.name for s in stance)]
        name = casadi_name(*names, "stance_sample")
        fn = ca.Function(
            name,
            [y, d],
            [ca.vertcat(*powers), ca.sum1(ca.vertcat(*losses)), ca.vertcat(*limited)],
        )
        adjoint = fn.reverse(1)
        library = compile_library(
            name, [fn, fn.jacobian(), fn.forward(1), adjoint, adjoint.jacobian()]
        )
        return load_external(name, library) or fn

    with SYMBOLIC_LOCK:
        return varying[0].built.get(key, build)


def _bounded_value(physics: LegPhysics, bound: Bound, q: ca.SX, qd: ca.SX, tau: ca.SX) -> ca.SX:
    """The quantity ``bound`` limits, for joint motion ``(q, qd)`` and torques ``tau``."""
    if bound.output == "tau":
        assert bound.row is not None
        return tau[bound.row]
    drive = physics.drives[bound.joint]
    outputs = drive.outputs(q[bound.joint], qd[bound.joint], tau[bound.joint])
    return outputs[bound.quantity]


def stance_limited_bounds(physics: LegPhysics) -> tuple[Bound, ...]:
    """The leg's bounds that its torques move: effort limits, torque-dependent drive bounds.

    A drive bound counts when its quantity depends on the torque (a cylinder's force; not its
    length or speed). Under whole-body loads the swinging legs change the stance legs'
    torques, so the swing NLP keeps these inside their limits on the stance samples it loads
    (less the problem's effort margin, :class:`~scalf_opt.energy.margins.LimitMargins`).
    """

    def build() -> tuple[Bound, ...]:  # symbolic, so once per leg (a search asks often)
        q, qd, tau = (ca.SX.sym(n, 2) for n in ("q", "qd", "tau"))
        return tuple(
            b
            for b in leg_bounds(physics)
            if b.output == "tau"
            or (b.row is None and ca.depends_on(_bounded_value(physics, b, q, qd, tau), tau))
        )

    return physics.built.get("stance limited bounds", build)


def stance_limit_function(physics: LegPhysics) -> ca.Function:
    """``(q, qd, tau) -> limited`` at one sample, the quantities of :func:`stance_limited_bounds`.

    The numeric twin of the stance kernel's third output: the pattern search and the limit
    checks evaluate the stance legs' limits with it (map it over the samples).
    """

    def build() -> ca.Function:
        q, qd, tau = (ca.SX.sym(n, 2) for n in ("q", "qd", "tau"))
        values = [_bounded_value(physics, b, q, qd, tau) for b in stance_limited_bounds(physics)]
        return ca.Function(
            casadi_name(physics.leg.name, "stance_limits"), [q, qd, tau], [ca.vertcat(*values)]
        )

    with SYMBOLIC_LOCK:
        return physics.built.get("stance limit function", build)
