"""Peaks of a cycle per leg and joint, set against the leg's limits.

For every joint: the largest torque, speed and charged power over the cycle, and the largest
magnitude of every drive output whose limits lie on both sides of zero (SCalf's cylinder force
and speed, HyQ's cylinder force: 3.2 kN of push, 1.96 kN of pull); each with the limit it must
respect, where it occurs, and whether it exceeds the limit. With different limits on the two
sides the peak is the sample closest to its side's limit, reported with that limit. Every other
bound (the joint range, the cylinder stroke) is checked too: :func:`cycle_violations`.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.energy.limits import Bound, Violation, leg_bounds, violations
from scalf_opt.energy.physics import LegPhysics
from scalf_opt.types import JOINT_ROLES

PEAK_QUANTITIES: tuple[tuple[str, str], ...] = (("tau", "nm"), ("qd", "rad_s"))
"""Two-row quantities whose magnitude is always reported (with their unit)."""


@dataclass(frozen=True)
class Peak:
    """The largest magnitude of one quantity of one joint over a cycle.

    Attributes:
        leg: Leg name.
        joint: ``hip`` or ``knee``.
        quantity: ``tau``, ``qd``, ``power`` or a drive channel (``cyl_force``, ``cyl_vel``).
        unit: Unit as in column names (``nm``, ``rad_s``, ``w``, ``n``, ``m_s``).
        value: The quantity at that sample (signed, SI).
        phase: ``stance`` or ``swing``.
        t_s: Cycle time of the sample [s].
        limit: The magnitude it must stay below (on the value's side, when the two sides'
            limits differ), ``None`` when it has no limit.
        source: Where the limit comes from.
        one_sided: The two sides have different limits (a cylinder's push and pull): the
            value's sign says which side ``limit`` is.
    """

    leg: str
    joint: str
    quantity: str
    unit: str
    value: float
    phase: str
    t_s: float
    limit: float | None
    source: str = ""
    one_sided: bool = False

    @property
    def exceeds(self) -> bool:
        """Beyond the limit by more than the round-off tolerance."""
        return self.limit is not None and abs(self.value) > self.limit * (1 + 1e-9)

    def as_dict(self) -> dict[str, Any]:
        """Plain data for JSON."""
        return {
            "value": self.value,
            "unit": self.unit,
            "phase": self.phase,
            "t_s": self.t_s,
            "limit": self.limit,
            "limit_source": self.source or None,
            "limit_of_the_values_side": self.one_sided,
            "exceeds": self.exceeds,
        }


TWO_ROW = frozenset({"tau", "qd", "power"})
"""Quantities stored as one (2, n) array with a row per joint; drive outputs are one per joint."""


def _samples(values: dict[str, np.ndarray], quantity: str, joint: int) -> np.ndarray | None:
    if quantity in TWO_ROW:
        return np.asarray(values[quantity], dtype=float)[joint]
    name = f"{quantity}_{JOINT_ROLES[joint]}"
    return np.asarray(values[name], dtype=float) if name in values else None


def _magnitude_bound(b: Bound) -> bool:
    """A bound on a magnitude: its limits on both sides of zero (not a range like a stroke)."""
    return b.symmetric or (b.lower < 0.0 < b.upper)


def _use(value: np.ndarray, bound: Bound | None) -> np.ndarray:
    """How much of its side's limit each sample uses (its magnitude without a bound)."""
    if bound is None or bound.symmetric:
        return np.abs(value)
    side = np.where(value >= 0.0, bound.upper, -bound.lower)
    return np.abs(value) / side  # inf limit on a side: 0 there


def _leg_peaks(cycle: RobotCycle, leg: str, bounds: tuple[Bound, ...]) -> list[Peak]:
    drive = {(b.quantity, b.unit): None for b in bounds if b.row is None and _magnitude_bound(b)}
    quantities = [*PEAK_QUANTITIES, *drive, ("power", "w")]
    leg_cycle = cycle.legs[leg]
    peaks = []
    for joint, role in enumerate(JOINT_ROLES):
        for quantity, unit in quantities:
            bound = next(
                (
                    b
                    for b in bounds
                    if b.quantity == quantity and b.joint == joint and _magnitude_bound(b)
                ),
                None,
            )
            best: tuple[float, float, str, float] | None = None  # use, value, phase, time
            for phase in (leg_cycle.stance, leg_cycle.swing):
                value = _samples(phase.values, quantity, joint)
                if value is None:
                    continue
                use = _use(value, bound)
                k = int(np.argmax(use))
                if best is None or use[k] > best[0]:
                    best = (float(use[k]), float(value[k]), phase.phase, float(phase.t_s[k]))
            if best is None:
                continue
            _, value_k, phase_name, t_k = best
            limit: float | None = None
            if bound is not None:
                limit = bound.upper if value_k >= 0.0 else -bound.lower
            source = bound.source if bound is not None else ""
            one_sided = bound is not None and not bound.symmetric
            peaks.append(
                Peak(leg, role, quantity, unit, value_k, phase_name, t_k, limit, source, one_sided)
            )
    return peaks


def cycle_peaks(cycle: RobotCycle, physics: dict[str, LegPhysics]) -> list[Peak]:
    """Peaks of every leg of ``cycle``: torque, speed, drive outputs with a limit, power."""
    out = []
    for leg in cycle.legs:
        out += _leg_peaks(cycle, leg, leg_bounds(physics[leg]))
    return out


@dataclass(frozen=True)
class CycleViolation:
    """A bound some sample of a leg's phase exceeds."""

    leg: str
    phase: str
    violation: Violation
    t_s: float

    def message(self) -> str:
        """One line: which leg, joint, quantity, value, bound, by how much and where."""
        b = self.violation.bound
        bound = f"limit {b.upper:g}" if b.symmetric else f"range [{b.lower:.6g}, {b.upper:.6g}]"
        over = 100.0 * self.violation.share
        return (
            f"{self.leg} {JOINT_ROLES[b.joint]}: {b.quantity} = {self.violation.value:.6g} "
            f"{b.printed_unit} exceeds its {b.source} ({bound}) by {over:.2g} % in {self.phase} "
            f"at t = {self.t_s:.4f} s"
        )


def cycle_violations(cycle: RobotCycle, physics: dict[str, LegPhysics]) -> list[CycleViolation]:
    """Every bound exceeded anywhere in the cycle, worst sample per leg, phase and bound."""
    out = []
    for leg, leg_cycle in cycle.legs.items():
        bounds = leg_bounds(physics[leg])
        for phase in (leg_cycle.stance, leg_cycle.swing):
            for v in violations(phase.values, bounds):
                out.append(CycleViolation(leg, phase.phase, v, float(phase.t_s[v.index])))
    return out


def peaks_summary(peaks: list[Peak]) -> dict[str, dict[str, dict[str, Any]]]:
    """``{leg: {"<quantity>_<joint>": peak record}}`` for ``summary.json``."""
    out: dict[str, dict[str, dict[str, Any]]] = {}
    for p in peaks:
        out.setdefault(p.leg, {})[f"{p.quantity}_{p.joint}"] = p.as_dict()
    return out
