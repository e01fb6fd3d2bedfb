"""The energy in a whole-robot joint log: every joint, per leg and phase, over each leg's cycles.

Per joint the mechanical power ``|tau qd|`` (the paper's accounting: decision 9) with the logged
rate, else the angle differentiated by the log filter (:mod:`~scalf_opt.logs.derivative`). Per
leg, its contacts (:mod:`~scalf_opt.logs.contacts`) give its touch-downs; each cycle runs from a
touch-down to the next (aligned on that leg's own touch-downs, never on the first sample), and
its energy is the integral of the piecewise-linear power over it, split into stance and swing by
the phase of each interval's first sample. A leg's period is the median time between its
touch-downs, its duty factor the mean share of its cycles in stance.

The robot's average power is the sum over legs of each leg's mean energy per cycle over its
period; the joints the sagittal model leaves out (the abduction: every leg joint but the hip
pitch and knee) are counted, and their share of the work is stated. With a speed (an odometry
topic, or given) the cost of transport ``P / (m g v)``.
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import pairwise
from typing import Any

import numpy as np

from scalf_opt.errors import LogError
from scalf_opt.locomotion.forces import GRAVITY_M_S2
from scalf_opt.logs.contacts import Contacts
from scalf_opt.logs.derivative import (
    DEFAULT_DEGREE,
    DEFAULT_HALF_WINDOW_S,
    half_window_samples,
    local_polynomial_derivative,
)
from scalf_opt.logs.robot_log import RobotLog

MIN_SAMPLES_PER_CYCLE = 40
"""Fewer samples per gait cycle than this and the energy misses the power's peaks (a warning)."""


@dataclass(frozen=True)
class JointEnergy:
    """One joint's mean mechanical energy per cycle of its leg [J]: stance, swing, cycle."""

    joint: str
    leg: str
    modelled: bool
    stance_j: float
    swing_j: float

    @property
    def cycle_j(self) -> float:
        """Stance plus swing [J]."""
        return self.stance_j + self.swing_j


@dataclass(frozen=True)
class LegCycles:
    """One leg's gait as the log shows it.

    Attributes:
        leg: Leg name.
        touchdowns_s: The times of its touch-downs that open a complete cycle, and the last
            one's end [s].
        period_s: The median time between its touch-downs [s].
        duty_cycle: The mean share of its cycles in stance.
        contact_method: ``foot force`` or ``motion``.
        per_cycle_j: The mechanical energy of each cycle, every joint of the leg [J].
    """

    leg: str
    touchdowns_s: np.ndarray
    period_s: float
    duty_cycle: float
    contact_method: str
    per_cycle_j: np.ndarray


@dataclass(frozen=True)
class RobotLogAnalysis:
    """The whole log's energies (module docstring).

    Attributes:
        source: The log.
        sample_rate_hz: Its median sample rate [Hz].
        velocity_source: ``measured`` (the log's rates) or ``filter``.
        joints: Every leg joint's energies, legs in log order, trunk first.
        legs: Per leg, its cycles.
        mass_kg: The robot's mass (for the cost of transport) [kg].
        speed_m_s: The forward speed [m/s], or ``None``.
        speed_source: ``odometry`` or ``given``, or ``None``.
        notes: The log's checks and this analysis's warnings, one line each.
    """

    source: str
    sample_rate_hz: float
    velocity_source: str
    joints: tuple[JointEnergy, ...]
    legs: dict[str, LegCycles]
    mass_kg: float
    speed_m_s: float | None
    speed_source: str | None
    notes: tuple[str, ...]

    def leg_energy_j(self, leg: str) -> dict[str, float]:
        """A leg's mean energy per cycle, every joint: ``stance``, ``swing``, ``cycle`` [J]."""
        mine = [j for j in self.joints if j.leg == leg]
        stance = sum(j.stance_j for j in mine)
        swing = sum(j.swing_j for j in mine)
        return {"stance": stance, "swing": swing, "cycle": stance + swing}

    @property
    def average_power_w(self) -> float:
        """Every joint's mean power, summed [W]."""
        return sum(j.cycle_j / self.legs[j.leg].period_s for j in self.joints)

    @property
    def left_out_share(self) -> float:
        """The share of the work done by the joints the sagittal model leaves out."""
        left_out = sum(j.cycle_j / self.legs[j.leg].period_s for j in self.joints if not j.modelled)
        total = self.average_power_w
        return left_out / total if total > 0 else 0.0

    @property
    def period_s(self) -> float:
        """The median of the legs' periods [s]."""
        return float(np.median([c.period_s for c in self.legs.values()]))

    @property
    def duty_cycle(self) -> float:
        """The mean of the legs' duty factors."""
        return float(np.mean([c.duty_cycle for c in self.legs.values()]))

    @property
    def cost_of_transport(self) -> float | None:
        """``P / (m g v)``, or ``None`` without a speed."""
        if not self.speed_m_s:
            return None
        return self.average_power_w / (self.mass_kg * GRAVITY_M_S2 * self.speed_m_s)

    def as_dict(self) -> dict[str, Any]:
        """Plain data: what ``analyze-log --json`` prints for a whole-robot log."""
        return {
            "source": self.source,
            "sample_rate_hz": self.sample_rate_hz,
            "velocity_source": self.velocity_source,
            "energy": "mechanical, sum |tau qd| over every leg joint (abduction included)",
            "period_s": self.period_s,
            "duty_cycle": self.duty_cycle,
            "legs": {
                leg: {
                    "period_s": c.period_s,
                    "duty_cycle": c.duty_cycle,
                    "contact_method": c.contact_method,
                    "cycles": len(c.per_cycle_j),
                    "first_touchdown_s": float(c.touchdowns_s[0]),
                    "mechanical_energy_per_cycle_j": self.leg_energy_j(leg),
                    "per_cycle_j": c.per_cycle_j.tolist(),
                }
                for leg, c in self.legs.items()
            },
            "joints": {
                j.joint: {
                    "leg": j.leg,
                    "in_sagittal_model": j.modelled,
                    "stance_j": j.stance_j,
                    "swing_j": j.swing_j,
                    "cycle_j": j.cycle_j,
                    "average_power_w": j.cycle_j / self.legs[j.leg].period_s,
                }
                for j in self.joints
            },
            "average_power_w": self.average_power_w,
            "left_out_share": self.left_out_share,
            "mass_kg": self.mass_kg,
            "speed_m_s": self.speed_m_s,
            "speed_source": self.speed_source,
            "cost_of_transport": self.cost_of_transport,
            "notes": list(self.notes),
        }


def joint_powers(
    log: RobotLog, half_window_s: float = DEFAULT_HALF_WINDOW_S, degree: int = DEFAULT_DEGREE
) -> tuple[dict[str, np.ndarray], str]:
    """Every joint's mechanical power ``|tau qd|`` at the samples [W], and the rates' source."""
    rates, source = joint_rates(log, half_window_s, degree)
    return {j: np.abs(log.tau_nm[j] * rates[j]) for j in log.tau_nm}, source


def joint_rates(
    log: RobotLog, half_window_s: float = DEFAULT_HALF_WINDOW_S, degree: int = DEFAULT_DEGREE
) -> tuple[dict[str, np.ndarray], str]:
    """Every joint's rate [rad/s]: the log's, else the filter's; and which."""
    if log.qd_rad_s is not None:
        return log.qd_rad_s, "measured"
    half = half_window_samples(log.sample_rate_hz, half_window_s, degree)
    if log.t_s.size < 2 * half + 1:
        raise LogError(
            f"{log.source}: {log.t_s.size} samples, fewer than the velocity filter's {2 * half + 1}"
        )
    joints = list(log.q_rad)
    rates = local_polynomial_derivative(
        log.t_s, np.vstack([log.q_rad[j] for j in joints]), half, degree
    )
    return dict(zip(joints, rates, strict=True)), "filter"


def _integrals(
    t: np.ndarray, power: np.ndarray, stance: np.ndarray, a: int | np.integer, b: int | np.integer
) -> tuple[float, float]:
    """Stance and swing energy of samples ``a..b``: trapezoids, each by its first sample's phase."""
    dt = np.diff(t[a : b + 1])
    area = 0.5 * (power[a:b] + power[a + 1 : b + 1]) * dt
    on = stance[a:b]
    return float(area[on].sum()), float(area[~on].sum())


def trot_speed_m_s(log: RobotLog, windows: list[tuple[float, float]]) -> float | None:
    """The trunk's mean horizontal speed over ``windows`` from the odometry, or ``None``."""
    if log.odometry is None:
        return None
    t, xy = log.odometry
    start = min(w[0] for w in windows)
    end = max(w[1] for w in windows)
    inside = (t >= start) & (t <= end)
    if inside.sum() < 2:
        inside = np.ones(t.size, dtype=bool)
    if inside.sum() < 2:
        raise LogError(f"{log.source}: the odometry has {int(inside.sum())} message: no speed")
    tt, pp = t[inside], xy[:, inside]
    return float(np.linalg.norm(pp[:, -1] - pp[:, 0]) / (tt[-1] - tt[0]))


def analyze_robot_log(
    log: RobotLog,
    contacts: Contacts,
    mass_kg: float,
    power_w: dict[str, np.ndarray],
    velocity_source: str,
    speed_m_s: float | None = None,
) -> RobotLogAnalysis:
    """Every joint's energy per cycle of its leg (module docstring).

    Args:
        log: The checked log.
        contacts: Each leg's stance samples.
        mass_kg: The robot's mass [kg].
        power_w: Per joint, its mechanical power at the samples (:func:`joint_powers`) [W].
        velocity_source: Where the rates came from: ``measured`` or ``filter``.
        speed_m_s: The forward speed [m/s]; ``None``: the odometry's, if the log has one.

    Raises:
        LogError: A leg with fewer than two touch-downs (no complete cycle).
    """
    t = log.t_s
    notes = list(log.notes)
    joints: list[JointEnergy] = []
    legs: dict[str, LegCycles] = {}
    for leg, leg_joints in log.legs.items():
        stance = contacts.stance[leg]
        downs = np.flatnonzero(stance[1:] & ~stance[:-1]) + 1
        if downs.size < 2:
            state = (
                "always on the ground"
                if stance.all()
                else ("never on the ground" if not stance.any() else f"{downs.size} touch-down")
            )
            raise LogError(
                f"{log.source}: leg {leg} ({contacts.method[leg]}): {state}: a cycle runs from a "
                "touch-down to the next: log at least two more periods"
            )
        per_joint = []
        per_cycle = np.zeros(downs.size - 1)
        for joint in leg_joints:
            power = power_w[joint]
            parts = [_integrals(t, power, stance, a, b) for a, b in pairwise(downs)]
            per_cycle += np.array([s + w for s, w in parts])
            per_joint.append(
                JointEnergy(
                    joint,
                    leg,
                    joint in log.leg_model_joints[leg],
                    float(np.mean([p[0] for p in parts])),
                    float(np.mean([p[1] for p in parts])),
                )
            )
        joints += per_joint
        lengths = np.diff(t[downs])
        in_stance = [
            float(np.sum(np.diff(t[a : b + 1])[stance[a:b]]) / (t[b] - t[a]))
            for a, b in pairwise(downs)
        ]
        legs[leg] = LegCycles(
            leg,
            t[downs],
            float(np.median(lengths)),
            float(np.mean(in_stance)),
            contacts.method[leg],
            per_cycle,
        )
    rate = float(1.0 / np.median(np.diff(t)))
    period = float(np.median([c.period_s for c in legs.values()]))
    if rate * period < MIN_SAMPLES_PER_CYCLE:
        notes.append(
            f"warning: {rate * period:.0f} samples per cycle ({rate:.4g} Hz at a {period:.3g} s "
            f"period), fewer than {MIN_SAMPLES_PER_CYCLE}: the energy misses the power's peaks"
        )
    speed_source = "given" if speed_m_s is not None else None
    if speed_m_s is None:
        windows = [(float(c.touchdowns_s[0]), float(c.touchdowns_s[-1])) for c in legs.values()]
        speed_m_s = trot_speed_m_s(log, windows)
        speed_source = "odometry" if speed_m_s is not None else None
    return RobotLogAnalysis(
        source=log.source,
        sample_rate_hz=rate,
        velocity_source=velocity_source,
        joints=tuple(joints),
        legs=legs,
        mass_kg=mass_kg,
        speed_m_s=speed_m_s,
        speed_source=speed_source,
        notes=tuple(notes),
    )
