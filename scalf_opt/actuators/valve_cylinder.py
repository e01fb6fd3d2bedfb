"""A hydraulic cylinder metered by a valve from a constant-pressure supply.

A valve-controlled (throttled) drive takes oil from a supply line held at the pressure ``p_s``
and returns it to the tank. Whatever the load, the oil that enters the cylinder comes at the
supply pressure: into the piston chamber (area ``A_p``) when the cylinder extends, into the rod
chamber (the annulus, ``A_a = A_p - A_rod``) when it retracts. The power drawn from the supply is
therefore pressure times flow::

    Q = A_p max(v, 0) + A_a max(-v, 0)        oil flow from the supply [m^3/s]
    P = p_s Q                                 power drawn from the supply [W]

with ``v = (dl/dq) qd`` the cylinder velocity (the mounting geometry of
:class:`~scalf_opt.actuators.cylinder.HydraulicCylinder`). Negative work costs flow like positive
work, and so does motion without load: the valve throttles away the difference between ``P`` and
the mechanical power (heat). ``P`` is everything the joint draws (:attr:`charges_joint_power` is
false), so the power accounting does not apply to it.

The supply can only push with ``p_s A_p`` and pull with ``p_s A_a``; the cylinder force
``tau / (dl/dq)`` is bounded accordingly (:meth:`output_bounds`, next to the stroke). Inside that
range the supply power is never below the mechanical power ``F v``: the throttle only dissipates.
The Stribeck friction of the base class, when the actuator file gives it, appears among the
outputs; it does not change ``P`` (the flow is set by the velocity alone).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import ClassVar

import casadi as ca

from scalf_opt.actuators.cylinder import HydraulicCylinder
from scalf_opt.actuators.drive import Channel, Drive, DriveKind, MaxFn
from scalf_opt.errors import ModelError
from scalf_opt.tables import Table
from scalf_opt.types import Expr

BAR_TO_PA = 1e5
SUPPLY_KEYS = ("joints", "pressure_bar", "bore_mm", "rod_mm")

VELOCITY_SCALE_M_S = 10.0
"""Unit in which the flow's ``max(v, 0)`` is taken [m/s]: with the NLP's smoothing width of 1e-4
in the argument's unit, the smooth flow is at most ``(A_p + A_a) * 0.5 mm/s`` above the exact one
(at ``v = 0``). SCalf's friction heat is smoothed 10x narrower, but the supply's kink is a hundred
times steeper (``p_s A_p``, kN, against the Stribeck force, 50 N): at 0.1 mm/s Ipopt does not
converge on HyQ in 3000 iterations, at 1 mm/s it does; every reported energy is the exact one.
"""


@dataclass(frozen=True)
class ValveControlledCylinder(HydraulicCylinder):
    """A cylinder fed through a valve from a supply at constant pressure.

    Attributes:
        supply_pressure_pa: Supply pressure ``p_s`` [Pa] (tank at 0).
        piston_area_m2: Piston area ``A_p`` [m^2], the extending side.
        annulus_area_m2: Annulus area ``A_a = A_p - A_rod`` [m^2], the retracting side.
    """

    supply_pressure_pa: float
    piston_area_m2: float
    annulus_area_m2: float

    kind: ClassVar[str] = "valve_cylinder"
    channels: ClassVar[tuple[Channel, ...]] = (
        *HydraulicCylinder.channels,
        Channel("flow", "m3_s", "oil flow from the supply A_p max(v, 0) + A_a max(-v, 0)"),
    )
    charges_joint_power: ClassVar[bool] = False
    power_text: ClassVar[str] = "supply pressure x flow of the valve-controlled cylinders"

    def __post_init__(self) -> None:
        if not 0.0 < self.annulus_area_m2 < self.piston_area_m2:
            raise ModelError(
                f"cylinder {self.joint_name}: annulus area {self.annulus_area_m2:g} m^2 must be "
                f"positive and below the piston area {self.piston_area_m2:g} m^2"
            )
        if not self.supply_pressure_pa > 0.0:
            raise ModelError(f"cylinder {self.joint_name}: supply pressure must be > 0")

    @classmethod
    def from_diameters(
        cls, cylinder: HydraulicCylinder, pressure_pa: float, bore_m: float, rod_m: float
    ) -> ValveControlledCylinder:
        """A cylinder's geometry fed from a supply; areas from the bore and rod diameters [m]."""
        piston = math.pi * bore_m**2 / 4.0
        return cls(
            joint_name=cylinder.joint_name,
            a_m=cylinder.a_m,
            b_m=cylinder.b_m,
            phi_offset_rad=cylinder.phi_offset_rad,
            angle_sign=cylinder.angle_sign,
            stroke_m=cylinder.stroke_m,
            friction=cylinder.friction,
            max_force_n=cylinder.max_force_n,
            max_speed_m_s=cylinder.max_speed_m_s,
            supply_pressure_pa=pressure_pa,
            piston_area_m2=piston,
            annulus_area_m2=piston - math.pi * rod_m**2 / 4.0,
        )

    def flow_m3_s(self, v: Expr, max_fn: MaxFn = ca.fmax) -> Expr:
        """Oil flow drawn from the supply at cylinder velocity ``v`` [m/s], in m^3/s."""
        u = v / VELOCITY_SCALE_M_S
        extend, retract = max_fn(u, 0), max_fn(-u, 0)
        return VELOCITY_SCALE_M_S * (self.piston_area_m2 * extend + self.annulus_area_m2 * retract)

    def outputs(self, q: Expr, qd: Expr, tau: Expr) -> dict[str, Expr]:  # noqa: D102
        out = super().outputs(q, qd, tau)
        out["flow"] = self.flow_m3_s(out["cyl_vel"])
        return out

    def loss_rate(self, q: Expr, qd: Expr, tau: Expr, max_fn: MaxFn = ca.fmax) -> Expr:
        """Power drawn from the supply ``p_s Q`` [W] (all the joint draws)."""
        return self.supply_pressure_pa * self.flow_m3_s(self.velocity_m_s(q, qd), max_fn)

    def force_limits_n(self) -> tuple[float, float]:
        """The cylinder force the supply can hold: ``(-p_s A_a, p_s A_p)`` [N]."""
        return (
            -self.supply_pressure_pa * self.annulus_area_m2,
            self.supply_pressure_pa * self.piston_area_m2,
        )

    def output_bounds(self, q_lower: float, q_upper: float) -> dict[str, tuple[float, float]]:
        """The stroke (as any cylinder), and the cylinder force inside the supply's reach."""
        bounds = dict(super().output_bounds(q_lower, q_upper))
        lo, hi = self.force_limits_n()
        if "cyl_force" in bounds:  # a limit of the cylinder itself: keep the tighter one
            lo, hi = max(lo, bounds["cyl_force"][0]), min(hi, bounds["cyl_force"][1])
        bounds["cyl_force"] = (lo, hi)
        return bounds

    def summary(self) -> str:  # noqa: D102
        lo, hi = self.force_limits_n()
        return (
            f"valve-controlled supply: {self.supply_pressure_pa * 1e-5:g} bar, piston "
            f"{self.piston_area_m2 * 1e6:.1f} mm^2, annulus {self.annulus_area_m2 * 1e6:.1f} mm^2; "
            f"force {lo:.0f}..{hi:.0f} N; power = pressure x flow"
        )


def read_supplies(file: Table, drives: Mapping[str, Drive]) -> dict[str, Drive]:
    """The cylinders each ``[supplies.<name>]`` feeds, as valve-controlled cylinders."""
    out: dict[str, Drive] = {}
    for table in file.tables("supplies").values():
        table.only(SUPPLY_KEYS)
        table.require(SUPPLY_KEYS)
        pressure = table.number("pressure_bar") * BAR_TO_PA
        bore, rod = table.number("bore_mm") * 1e-3, table.number("rod_mm") * 1e-3
        if rod >= bore:
            raise file.error(f"{table.key('rod_mm')} must be below {table.key('bore_mm')}")
        for joint in table.names("joints"):
            cylinder = drives.get(joint)
            if not isinstance(cylinder, HydraulicCylinder):
                raise file.error(
                    f"{table.key('joints')} names {joint}, which has no [cylinders.{joint}] table"
                )
            if joint in out:
                raise file.error(
                    f"{table.key('joints')} names {joint}, already fed by another supply"
                )
            out[joint] = ValveControlledCylinder.from_diameters(cylinder, pressure, bore, rod)
    return out


SUPPLIES = DriveKind(
    tables=("supplies",),
    read=read_supplies,
    help=(
        "[supplies.<name>]: a constant-pressure supply (pressure_bar, bore_mm, rod_mm) and the "
        "joints whose cylinders it feeds through valves"
    ),
    replaces=True,
)
"""HyQ's valve-controlled cylinders: supply pressure x flow."""
