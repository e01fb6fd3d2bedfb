"""SCalf's hydraulic cylinder: mounting geometry (Table 2, decision 7) and Stribeck friction.

A cylinder spans the triangle formed by its two mounting arms ``a`` and ``b``, which meet at the
joint axis with angle ``phi``; by the law of cosines (Eq. 52)::

    l(theta)      = sqrt(a^2 + b^2 - 2 a b cos(phi)),     phi = phi_offset + sign * theta
    dl/dtheta     = sign * a b sin(phi) / l                  [m/rad]
    v             = (dl/dtheta) theta_dot                     cylinder velocity [m/s]
    F_cylinder    = tau / (dl/dtheta)                         virtual work [N]
    theta(l)      = sign * (acos((a^2 + b^2 - l^2) / (2 a b)) - phi_offset)    inverse (Eq. 67)
    tau           = F_cylinder * dl/dtheta                    from a measured force (Eq. 68)

For the RF leg, hip ``phi = (90 deg - e1 - e2) - theta`` and knee ``phi = theta - (e3 - e4)``;
hind legs use the negated angle (the ``sign`` flips). The friction heat ``|F_f(v) v|``
(:mod:`scalf_opt.actuators.stribeck`) is the drive's loss; the joint's mechanical power is charged
through the accounting (decision 9).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, ClassVar

import casadi as ca
import numpy as np

from scalf_opt.actuators.drive import Channel, Drive, DriveKind, MaxFn
from scalf_opt.actuators.stribeck import StribeckBranch, StribeckFriction
from scalf_opt.errors import ModelError
from scalf_opt.tables import Table
from scalf_opt.types import Expr


@dataclass(frozen=True)
class HydraulicCylinder(Drive):
    """A joint's hydraulic cylinder.

    Attributes:
        joint_name: URDF joint it drives.
        a_m: Mounting arm a [m].
        b_m: Mounting arm b [m].
        phi_offset_rad: Arm angle at theta = 0 [rad].
        angle_sign: +1 or -1: ``phi = phi_offset + angle_sign * theta``.
        stroke_m: Piston stroke [m].
        friction: Friction law of the cylinder.
        max_force_n: Largest force the cylinder may carry, pushing or pulling [N] (inf: no
            limit). Keyword-only, like ``max_speed_m_s``, so that subclasses can add fields.
        max_speed_m_s: Largest piston speed, extending or retracting [m/s] (inf: no limit).
    """

    a_m: float
    b_m: float
    phi_offset_rad: float
    angle_sign: int
    stroke_m: float
    friction: StribeckFriction
    max_force_n: float = field(default=math.inf, kw_only=True)
    max_speed_m_s: float = field(default=math.inf, kw_only=True)

    kind: ClassVar[str] = "cylinder"
    noun: ClassVar[str] = "cylinder"
    file_table: ClassVar[str] = "cylinders"
    channels: ClassVar[tuple[Channel, ...]] = (
        Channel("cyl_len", "m", "cylinder length l(q)"),
        Channel("cyl_vel", "m_s", "cylinder velocity (dl/dq) qd"),
        Channel("cyl_force", "n", "cylinder force tau / (dl/dq)"),
        Channel("friction", "n", "Stribeck friction force F_f(v) of the cylinder"),
    )

    def angle_rad(self, theta: Expr) -> Expr:
        """Angle between the mounting arms, ``phi = phi_offset + angle_sign * theta`` [rad]."""
        return self.phi_offset_rad + self.angle_sign * theta

    def length_m(self, theta: Expr) -> Expr:
        """Cylinder length ``l = sqrt(a^2 + b^2 - 2 a b cos(phi))`` [m] (Eq. 52, decision 7)."""
        phi = self.angle_rad(theta)
        return ca.sqrt(self.a_m**2 + self.b_m**2 - 2 * self.a_m * self.b_m * ca.cos(phi))

    def angle_from_length_rad(self, length_m: Expr) -> Expr:
        """Joint angle from the cylinder length [rad]: the inverse of :meth:`length_m` (Eq. 67).

        ``phi = acos((a^2 + b^2 - l^2) / (2 a b))`` and ``theta = angle_sign (phi - phi_offset)``.
        ``acos`` returns the arm angle in ``[0, pi]``, the branch on which :meth:`length_m` is
        monotonic and which :meth:`stroke_limits_m` checks the joint range stays on, so the
        inverse is exact over the stroke.
        """
        cos_phi = (self.a_m**2 + self.b_m**2 - length_m**2) / (2 * self.a_m * self.b_m)
        return self.angle_sign * (ca.acos(cos_phi) - self.phi_offset_rad)

    def moment_arm_m(self, theta: Expr) -> Expr:
        """Signed moment arm ``dl/dtheta = angle_sign * a b sin(phi) / l`` [m/rad]."""
        phi = self.angle_rad(theta)
        return self.angle_sign * self.a_m * self.b_m * ca.sin(phi) / self.length_m(theta)

    def velocity_m_s(self, theta: Expr, theta_dot: Expr) -> Expr:
        """Cylinder velocity ``(dl/dtheta) theta_dot`` [m/s]."""
        return self.moment_arm_m(theta) * theta_dot

    def outputs(self, q: Expr, qd: Expr, tau: Expr) -> dict[str, Expr]:  # noqa: D102
        arm = self.moment_arm_m(q)
        vel = arm * qd
        return {
            "cyl_len": self.length_m(q),
            "cyl_vel": vel,
            "cyl_force": tau / arm,
            "friction": self.friction.force_n(vel),
        }

    def loss_rate(self, q: Expr, qd: Expr, tau: Expr, max_fn: MaxFn = ca.fmax) -> Expr:
        """Friction heat ``|F_f(v) v|`` [W] (decisions 8, 9)."""
        return self.friction.heat_rate_w(self.velocity_m_s(q, qd), max_fn)

    def output_bounds(self, q_lower: float, q_upper: float) -> dict[str, tuple[float, float]]:
        """The length inside the stroke (decision 14); force and speed inside their limits."""
        bounds = {"cyl_len": self.stroke_limits_m(q_lower, q_upper)}
        if math.isfinite(self.max_force_n):
            bounds["cyl_force"] = (-self.max_force_n, self.max_force_n)
        if math.isfinite(self.max_speed_m_s):
            bounds["cyl_vel"] = (-self.max_speed_m_s, self.max_speed_m_s)
        return bounds

    def stroke_limits_m(self, theta_lower: float, theta_upper: float) -> tuple[float, float]:
        """Cylinder length range allowed by the stroke [m] (decision 14).

        ``l_min`` is the shorter of the lengths at the two joint limits and
        ``l_max = l_min + stroke``. ``l`` is monotonic in ``theta`` over the range because
        ``dl/dphi = a b sin(phi) / l`` keeps its sign while ``phi`` stays inside ``(0, pi)``;
        this is verified.

        Raises:
            ModelError: The mounting angle leaves ``(0, pi)`` over the range (not monotonic).
        """
        phis = [float(self.angle_rad(t)) for t in (theta_lower, theta_upper)]
        if not all(0.0 < p < math.pi for p in phis):
            raise ModelError(
                f"cylinder {self.joint_name}: mounting angle phi goes from {phis[0]:.4f} to "
                f"{phis[1]:.4f} rad over the joint range [{theta_lower}, {theta_upper}] rad, "
                "outside (0, pi): the cylinder length is not monotonic"
            )
        shortest = min(float(self.length_m(t)) for t in (theta_lower, theta_upper))
        return shortest, shortest + self.stroke_m

    def described(self, q_lower: float, q_upper: float) -> dict[str, Any]:
        """The mounting geometry and the length range over the joint range (SI)."""
        grid = np.linspace(q_lower, q_upper, 2001)
        lengths = np.array([float(self.length_m(x)) for x in grid])
        return {
            "a_m": self.a_m,
            "b_m": self.b_m,
            "phi_offset_rad": self.phi_offset_rad,
            "angle_sign": self.angle_sign,
            "stroke_m": self.stroke_m,
            "length_range_m": [float(lengths.min()), float(lengths.max())],
        }


# --- the actuator file's [friction] and [cylinders.<joint>] tables --------------------------------

FRICTIONLESS = StribeckFriction(
    StribeckBranch(0.0, 0.0, 0.0, 1.0), StribeckBranch(0.0, 0.0, 0.0, 1.0)
)
"""No friction, for supply-fed cylinders of a file without a ``[friction]`` table."""

BRANCH_KEYS = ("viscous_n_s_per_m", "static_n", "coulomb_n", "stribeck_velocity_m_s")
GEOMETRY_KEYS = ("a_mm", "b_mm", "phi_offset_deg", "angle_sign", "stroke_mm")
LIMIT_KEYS = ("max_force_n", "max_speed_m_s")


def read_friction(file: Table) -> StribeckFriction | None:
    """``[friction.extend]`` and ``[friction.retract]``; ``None`` without ``[friction]``."""
    if "friction" not in file:
        return None
    table = file.table("friction")
    table.only(("extend", "retract"))
    branches = []
    for key in ("extend", "retract"):
        branch = table.table(key)
        branch.only(BRANCH_KEYS)
        branch.require(BRANCH_KEYS)
        branches.append(StribeckBranch(*(branch.number(k) for k in BRANCH_KEYS)))
    return StribeckFriction(extend=branches[0], retract=branches[1])


def read_cylinder(joint: str, table: Table, friction: StribeckFriction) -> HydraulicCylinder:
    """One ``[cylinders.<joint>]`` table; millimetres and degrees converted to SI."""
    table.only(GEOMETRY_KEYS + LIMIT_KEYS)
    table.require(GEOMETRY_KEYS)
    limits = {key: table.number(key) for key in LIMIT_KEYS if key in table}
    return HydraulicCylinder(
        joint_name=joint,
        a_m=table.number("a_mm") * 1e-3,
        b_m=table.number("b_mm") * 1e-3,
        phi_offset_rad=math.radians(table.number("phi_offset_deg", positive=False)),
        angle_sign=table.sign("angle_sign"),
        stroke_m=table.number("stroke_mm") * 1e-3,
        friction=friction,
        **limits,
    )


def read_cylinders(file: Table, drives: Mapping[str, Drive]) -> dict[str, Drive]:
    """Every ``[cylinders.<joint>]``, with the file's friction.

    Without ``[friction]`` the cylinders are frictionless and :func:`check_friction` asks that
    each be fed by a supply.
    """
    friction = read_friction(file)
    tables = file.tables("cylinders")
    if "cylinders" in file and not tables:
        raise file.error("[cylinders] is empty")
    return {j: read_cylinder(j, t, friction or FRICTIONLESS) for j, t in tables.items()}


def check_friction(file: Table, drives: Mapping[str, Drive]) -> None:
    """A cylinder not fed by a supply charges its friction heat: the file needs ``[friction]``."""
    plain = [j for j, d in drives.items() if type(d) is HydraulicCylinder]
    if plain and "friction" not in file:
        raise file.error(
            f"missing table [friction] (cylinder {plain[0]} is not fed by a supply and "
            "charges its friction heat)"
        )


CYLINDERS = DriveKind(
    tables=("friction", "cylinders"),
    read=read_cylinders,
    help=(
        "[friction.extend], [friction.retract]: Stribeck friction of every cylinder "
        "(viscous_n_s_per_m, static_n, coulomb_n, stribeck_velocity_m_s); "
        "[cylinders.<joint>]: a cylinder's mounting (a_mm, b_mm, phi_offset_deg, angle_sign, "
        "stroke_mm; optional max_force_n, max_speed_m_s)"
    ),
    check=check_friction,
)
"""SCalf's cylinders: joint power plus Stribeck friction heat."""
