"""An electric joint drive: a motor behind a gearbox, its copper loss and the joint's friction.

The motor turns ``N`` times faster than the joint and supplies the joint torque plus the joint
friction (Coulomb and viscous, at the joint)::

    tau_f     = tau_c sign(qd) + b qd                  joint friction torque [N m]
    i         = (tau + tau_f) / (N k_t)                motor current [A]
    P_copper  = R i^2 = R (tau + tau_f)^2 / (N k_t)^2   copper loss in the winding [W]
    P_el      = (tau + tau_f) qd + P_copper            electrical power at the motor [W]

(the motor's mechanical power is ``tau_m omega_m = (tau + tau_f) / N * N qd``). ``P_el`` is
negative when the joint brakes hard enough for the motor to generate. Without regeneration (the
default: a bus that cannot take energy back burns it in a brake resistor) the drive draws
``max(P_el, 0)``; with regeneration it draws ``P_el`` and the negative part is recovered.

The drive meters its own input power, so the joint's mechanical power is not charged a second
time through the accounting (:attr:`charges_joint_power` is false): :meth:`loss_rate` is all it
draws. Over a periodic motion with regeneration, the energy drawn is the copper loss plus the
friction heat (``tau qd`` integrates to zero): the energy balance the tests check.

For the NLP the two non-smooth operations use the supplied ``max_fn`` (see
:class:`~scalf_opt.actuators.drive.Drive`; its smoothing width is ``eps = 1e-4`` in the unit of
its argument): ``sign(qd)`` becomes ``(max(x, 0) - max(-x, 0)) / (max(x, 0) + max(-x, 0))`` with
``x = qd / SPEED_SCALE_RAD_S`` (exactly ``sign`` with the exact max, a smooth step
``x / sqrt(x^2 + eps^2)`` 0.01 rad/s wide with the smooth one) and ``max(P_el, 0)`` is taken on
``P_el / POWER_SCALE_W`` (a smoothing width of 0.1 W). Narrower widths leave Ipopt a nearly
non-smooth objective that it does not solve in 3000 iterations on the catalog's electric robots;
these widths let it converge on all of them, and every reported energy is the exact one.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import ClassVar

import casadi as ca

from scalf_opt.actuators.drive import Channel, Drive, DriveKind, MaxFn
from scalf_opt.tables import Table
from scalf_opt.types import Expr

POWER_SCALE_W = 1000.0
"""Unit in which ``max(P_el, 0)`` is taken [W]: with the NLP's smoothing width of 1e-4 in the
argument's unit, the smooth max is at most 0.05 W above the exact one (at ``P_el = 0``)."""

SPEED_SCALE_RAD_S = 100.0
"""Unit in which ``sign(qd)`` of the Coulomb friction is taken [rad/s]: with the NLP's smoothing
width of 1e-4, the smooth sign rises from -0.7 to 0.7 over 0.02 rad/s."""

_TINY = 1e-300
"""Keeps ``0 / 0`` out of the exact ``sign(0)``, which is 0."""


def direction(x: Expr, max_fn: MaxFn = ca.fmax) -> Expr:
    """``sign(x)`` built from ``max_fn``: exact with :func:`casadi.fmax`, smooth with a smooth max.

    ``(max(x, 0) - max(-x, 0)) / (max(x, 0) + max(-x, 0))`` is ``+1``, ``-1`` or ``0`` (at
    ``x = 0``) with the exact max, and ``x / sqrt(x^2 + eps^2)`` with the smooth max
    ``(x + sqrt(x^2 + eps^2)) / 2``.
    """
    pos, neg = max_fn(x, 0), max_fn(-x, 0)
    return (pos - neg) / ca.fmax(pos + neg, _TINY)


@dataclass(frozen=True)
class ElectricDrive(Drive):
    """A geared electric motor driving one joint.

    Attributes:
        joint_name: URDF joint it drives.
        gear_ratio: Motor turns per joint turn ``N`` (> 0).
        torque_constant_nm_per_a: Motor torque per ampere ``k_t`` [N m/A] (> 0).
        winding_resistance_ohm: Winding resistance ``R`` [ohm] (>= 0), such that the copper
            loss is ``R i^2`` with ``i`` the torque-producing current.
        coulomb_friction_nm: Coulomb friction at the joint ``tau_c`` [N m] (>= 0).
        viscous_friction_nm_s_per_rad: Viscous friction at the joint ``b`` [N m s/rad] (>= 0).
        regenerative: Negative electrical power is recovered (default: burnt, costs nothing).
    """

    gear_ratio: float
    torque_constant_nm_per_a: float
    winding_resistance_ohm: float
    coulomb_friction_nm: float = 0.0
    viscous_friction_nm_s_per_rad: float = 0.0
    regenerative: bool = False

    kind: ClassVar[str] = "electric"
    noun: ClassVar[str] = "electric drive"
    file_table: ClassVar[str] = "electric"
    channels: ClassVar[tuple[Channel, ...]] = (
        Channel("motor_current", "a", "motor current (tau + tau_f) / (N k_t)"),
        Channel("copper_loss", "w", "copper loss R i^2 in the motor winding"),
        Channel("electric_power", "w", "electrical power at the motor, negative when generating"),
    )
    charges_joint_power: ClassVar[bool] = False
    power_text: ClassVar[str] = (
        "the electric motors' work with the joint friction plus their copper loss (none "
        "recovered unless regenerative)"
    )

    def friction_torque_nm(self, qd: Expr, max_fn: MaxFn = ca.fmax) -> Expr:
        """Joint friction torque ``tau_c sign(qd) + b qd`` [N m] (opposes the motion)."""
        return self.coulomb_friction_nm * direction(qd / SPEED_SCALE_RAD_S, max_fn) + (
            self.viscous_friction_nm_s_per_rad * qd
        )

    def motor_current_a(self, qd: Expr, tau: Expr, max_fn: MaxFn = ca.fmax) -> Expr:
        """Torque-producing motor current ``(tau + tau_f) / (N k_t)`` [A]."""
        load = tau + self.friction_torque_nm(qd, max_fn)
        return load / (self.gear_ratio * self.torque_constant_nm_per_a)

    def copper_loss_w(self, qd: Expr, tau: Expr, max_fn: MaxFn = ca.fmax) -> Expr:
        """Copper loss ``R i^2`` [W]."""
        return self.winding_resistance_ohm * self.motor_current_a(qd, tau, max_fn) ** 2

    def electric_power_w(self, qd: Expr, tau: Expr, max_fn: MaxFn = ca.fmax) -> Expr:
        """Electrical power at the motor ``(tau + tau_f) qd + R i^2`` [W] (signed)."""
        load = tau + self.friction_torque_nm(qd, max_fn)
        return load * qd + self.copper_loss_w(qd, tau, max_fn)

    def outputs(self, q: Expr, qd: Expr, tau: Expr) -> dict[str, Expr]:  # noqa: D102
        return {
            "motor_current": self.motor_current_a(qd, tau),
            "copper_loss": self.copper_loss_w(qd, tau),
            "electric_power": self.electric_power_w(qd, tau),
        }

    def loss_rate(self, q: Expr, qd: Expr, tau: Expr, max_fn: MaxFn = ca.fmax) -> Expr:
        """Power drawn from the bus [W]: ``max(P_el, 0)``, or ``P_el`` when regenerative."""
        power = self.electric_power_w(qd, tau, max_fn)
        if self.regenerative:
            return power
        return max_fn(power / POWER_SCALE_W, 0) * POWER_SCALE_W

    def summary(self) -> str:  # noqa: D102
        regen = "regenerative" if self.regenerative else "no regeneration"
        return (
            f"electric drive: gear {self.gear_ratio:g}:1, k_t {self.torque_constant_nm_per_a:g} "
            f"N m/A, R {self.winding_resistance_ohm:g} ohm, joint friction "
            f"{self.coulomb_friction_nm:g} N m + {self.viscous_friction_nm_s_per_rad:g} N m s/rad, "
            f"{regen}"
        )


REQUIRED_KEYS = ("joints", "gear_ratio", "torque_constant_nm_per_a", "winding_resistance_ohm")
OPTIONAL_KEYS = ("coulomb_friction_nm", "viscous_friction_nm_s_per_rad", "regenerative")


def read_motors(file: Table, drives: Mapping[str, Drive]) -> dict[str, Drive]:
    """The joints each ``[electric.<name>]`` drives, as electric drives."""
    out: dict[str, Drive] = {}
    for table in file.tables("electric").values():
        table.only(REQUIRED_KEYS + OPTIONAL_KEYS)
        table.require(REQUIRED_KEYS)
        regenerative = table.boolean("regenerative", False)
        values = {
            "gear_ratio": table.number("gear_ratio"),
            "torque_constant_nm_per_a": table.number("torque_constant_nm_per_a"),
            **{
                key: table.number(key, zero=True, default=0.0 if key in OPTIONAL_KEYS else None)
                for key in (
                    "winding_resistance_ohm",
                    "coulomb_friction_nm",
                    "viscous_friction_nm_s_per_rad",
                )
            },
        }
        for joint in table.names("joints"):
            if joint in out:
                raise file.error(
                    f"{table.key('joints')} names {joint}, already driven by another motor"
                )
            out[joint] = ElectricDrive(joint_name=joint, regenerative=regenerative, **values)
    return out


MOTORS = DriveKind(
    tables=("electric",),
    read=read_motors,
    help=(
        "[electric.<name>]: a geared motor (gear_ratio, torque_constant_nm_per_a, "
        "winding_resistance_ohm; optional coulomb_friction_nm, viscous_friction_nm_s_per_rad, "
        "regenerative) and the joints it drives"
    ),
)
"""Geared electric motors: electrical power with copper loss."""
