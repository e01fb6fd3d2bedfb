"""Stribeck friction of a hydraulic cylinder (Eq. 50-51, decision 8) and its heat rate.

With the parameter row chosen by the sign of the cylinder velocity ``v`` (extension ``v > 0``,
retraction ``v < 0``)::

    F_f(v) = sign(v) g(|v|) + B v,       g(u) = F_c + (F_s - F_c) exp(-u / v_s)

and the heat rate is ``|F_f(v) v| = h_ext(max(v, 0)) + h_ret(max(-v, 0))`` with
``h(u) = u g(u) + B u^2`` (exact, because ``h(0) = 0`` and ``F_f(v) v >= 0``). Replacing ``max``
by a smooth max gives the NLP's differentiable heat. Every formula accepts floats, DM, SX and MX.
"""

from __future__ import annotations

from dataclasses import dataclass

import casadi as ca

from scalf_opt.actuators.drive import MaxFn
from scalf_opt.types import Expr


@dataclass(frozen=True)
class StribeckBranch:
    """Stribeck parameters for one direction of motion (one row of the paper's friction table).

    Attributes:
        viscous_n_s_per_m: Viscous coefficient B [N s/m].
        static_n: Static (break-away) friction F_s [N].
        coulomb_n: Coulomb friction F_c [N].
        stribeck_velocity_m_s: Stribeck velocity v_s [m/s].
    """

    viscous_n_s_per_m: float
    static_n: float
    coulomb_n: float
    stribeck_velocity_m_s: float

    def breakaway_n(self, speed_m_s: Expr) -> Expr:
        """``g(u) = F_c + (F_s - F_c) exp(-u / v_s)`` [N] at a speed ``u >= 0`` [m/s]."""
        decay = ca.exp(-speed_m_s / self.stribeck_velocity_m_s)
        return self.coulomb_n + (self.static_n - self.coulomb_n) * decay

    def heat_rate_w(self, speed_m_s: Expr) -> Expr:
        """``h(u) = u g(u) + B u^2`` [W] at a speed ``u >= 0`` [m/s]."""
        return speed_m_s * self.breakaway_n(speed_m_s) + self.viscous_n_s_per_m * speed_m_s**2


@dataclass(frozen=True)
class StribeckFriction:
    """Asymmetric cylinder friction: one branch per direction (decision 8).

    Attributes:
        extend: Parameters for a cylinder velocity v > 0.
        retract: Parameters for a cylinder velocity v < 0.
    """

    extend: StribeckBranch
    retract: StribeckBranch

    def force_n(self, v: Expr) -> Expr:
        """Friction force ``F_f(v)`` [N] at cylinder velocity ``v`` [m/s]; ``F_f(0) = 0``.

        It jumps from ``-F_s`` to ``+F_s`` across ``v = 0`` (both rows have F_s = 50 N for
        SCalf).
        """
        speed = ca.fabs(v)
        ext = self.extend.breakaway_n(speed) + self.extend.viscous_n_s_per_m * v
        ret = -self.retract.breakaway_n(speed) + self.retract.viscous_n_s_per_m * v
        return ca.if_else(v > 0, ext, ca.if_else(v < 0, ret, 0.0))

    def heat_rate_w(self, v: Expr, max_fn: MaxFn = ca.fmax) -> Expr:
        """Friction heat rate ``|F_f(v) v|`` [W] at cylinder velocity ``v`` [m/s].

        Written as ``h_extend(max(v, 0)) + h_retract(max(-v, 0))``, which equals ``|F_f(v) v|``
        exactly: only one of the two speeds is non-zero, ``h(0) = 0`` and ``F_f(v) v >= 0``.
        With ``max_fn = ca.fmax`` it is exact (kinked at ``v = 0``); with a smooth max (see
        :func:`smooth_max`) it is differentiable everywhere, as the NLP needs.
        """
        return self.extend.heat_rate_w(max_fn(v, 0)) + self.retract.heat_rate_w(max_fn(-v, 0))


def smooth_max(x: Expr, eps: float) -> Expr:
    """Smooth ``max(x, 0) = (x + sqrt(x^2 + eps^2)) / 2``.

    It is infinitely differentiable, always above ``max(x, 0)`` and at most ``eps / 2`` above it
    (the gap is largest at ``x = 0`` and falls like ``eps^2 / (4 |x|)``); it tends to ``max(x, 0)``
    as ``eps -> 0``.

    Args:
        x: Argument (float, DM, SX or MX), e.g. a cylinder velocity [m/s].
        eps: Smoothing width in the unit of ``x`` (> 0). For cylinder velocities choose it well
            below the Stribeck velocities (7 and 15 mm/s), e.g. 1e-4 m/s, so the smoothed heat
            differs from the exact one only near ``v = 0``, where both are tiny.
    """
    return 0.5 * (x + ca.sqrt(x**2 + eps**2))
