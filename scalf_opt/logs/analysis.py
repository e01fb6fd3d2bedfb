"""The energy in a cylinder log, per leg and phase over complete gait cycles (Table 7).

Per leg and cylinder (hip pitch, knee):

1. the joint angle from the length, ``theta = theta(l)``, the inverse of the cylinder's
   law-of-cosines length (Eq. 67, ``HydraulicCylinder.angle_from_length_rad``);
2. the cylinder velocity ``v = dl/dt`` by the local quadratic fit of
   :mod:`~scalf_opt.logs.derivative` (Savitzky-Golay on the actual time stamps);
3. the joint torque ``tau = F dl/dtheta`` (Eq. 68) and rate ``theta_dot = v / (dl/dtheta)``,
   charged through the model's own power formula
   (:meth:`~scalf_opt.energy.physics.LegPhysics.power_function`): the mechanical power
   ``|tau theta_dot| = |F v|``, and beside it the cylinders' Stribeck friction heat at ``v``
   (not measured by a rod force sensor: the model's estimate);
4. energies as the integral of the piecewise-linear interpolant of the sampled power over each
   complete cycle, split into stance and swing by the phase of each sample.

Cycles: each leg's cycle starts at its touch-down, with the gait period ``T``. Phases and
touch-downs come from the ``contact`` column when the log has one; without it, from the trot's
schedule with the log's time origin at RF's (and LH's) touch-down. ``T`` is ``--period`` when
given, else the median time between a leg's touch-downs (contact column, when a leg touches down
twice), else the gait's period.
A complete cycle is a window ``[t_0 + k T, t_0 + (k + 1) T]`` inside the leg's samples, ``t_0``
its first touch-down in the log.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from scalf_opt.actuators.cylinder import HydraulicCylinder
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import LogError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.trot import stance_start_s
from scalf_opt.logs.derivative import (
    DEFAULT_DEGREE,
    DEFAULT_HALF_WINDOW_S,
    half_window_samples,
    local_polynomial_derivative,
)
from scalf_opt.logs.log_file import LENGTH_COLUMNS, TIME, CylinderLog, LegLog
from scalf_opt.types import JOINT_ROLES

STROKE_TOLERANCE_M = 1e-4
"""A length may read this far outside the stroke (the position sensor's accuracy) [m]."""


@dataclass(frozen=True)
class LegEnergy:
    """One leg's energies, mean per complete cycle.

    Attributes:
        leg: Leg name.
        windows_s: The complete cycles ``(start, end)`` [s].
        mechanical_j: Mean mechanical energy ``sum |F v|`` per cycle: ``stance``, ``swing``,
            ``cycle`` [J].
        per_cycle_j: The mechanical energy of each cycle [J].
        friction_heat_j: Mean friction heat per cycle (the model's Stribeck law at the
            measured velocity) [J].
    """

    leg: str
    windows_s: list[tuple[float, float]]
    mechanical_j: dict[str, float]
    per_cycle_j: list[float]
    friction_heat_j: float


def cycle_windows(
    t_s: np.ndarray,
    contact: np.ndarray | None,
    gait: Gait,
    leg: str,
    period_s: float,
    source: str,
) -> tuple[np.ndarray, list[tuple[float, float]]]:
    """A leg's stance samples and its complete cycles ``(start, end)`` [s] in a log.

    With contact flags the cycles start at the first touch-down; without, the gait's schedule
    (scaled to ``period_s``) says where the leg's stance starts and how long it lasts.

    Raises:
        LogError: The samples hold no complete cycle (``source`` names where, in the message).
    """
    if contact is not None:
        stance = contact
    else:
        offset = stance_start_s(gait, leg) * period_s / gait.period_s
        stance = np.mod(t_s - offset, period_s) < gait.duty_cycle * period_s
    first = first_touchdown_s(t_s, contact, gait, leg, period_s)
    count = int(np.floor((t_s[-1] - first) / period_s + 1e-9)) if np.isfinite(first) else 0
    if count < 1:
        raise no_complete_cycle(source, leg, t_s, first, period_s, stance)
    windows = [(first + k * period_s, first + (k + 1) * period_s) for k in range(count)]
    return stance, windows


def first_touchdown_s(
    t_s: np.ndarray, contact: np.ndarray | None, gait: Gait, leg: str, period_s: float
) -> float:
    """Where a leg's first cycle in a log starts: its first touch-down [s].

    With contact flags, the first 0 -> 1 step (``inf`` when there is none: a log that starts in
    contact may start in mid-stance, so its first sample is no touch-down); without, the first
    stance start of the gait's schedule (scaled to ``period_s``) at or after the first sample.
    """
    if contact is not None:
        downs = touchdowns(contact, t_s)
        return float(downs[0]) if downs.size else np.inf
    offset = stance_start_s(gait, leg) * period_s / gait.period_s
    return float(offset + np.ceil((t_s[0] - offset) / period_s) * period_s)


def no_complete_cycle(
    source: str,
    leg: str,
    t_s: np.ndarray,
    first_s: float,
    period_s: float,
    stance: np.ndarray,
) -> LogError:
    """The error for a leg whose samples hold no complete cycle from its first touch-down.

    ``stance``: whether each sample is in stance (the log's contact column, if it has one).
    """
    if not np.isfinite(first_s):
        if stance.all() or not stance.any():
            where = "in contact at every sample" if stance.all() else "never in contact"
            return LogError(
                f"{source}: leg {leg} is {where} (its contact column has no 0 -> 1 step), "
                "so the log holds no gait cycle of it"
            )
        return LogError(
            f"{source}: leg {leg} never touches down in the log (its contact column has no "
            "0 -> 1 step), so it holds no complete gait cycle (a cycle runs from a touch-down "
            "to the next: log at least two more periods)"
        )
    return LogError(
        f"{source}: leg {leg} has no complete gait cycle: one period ({period_s:.4g} s) from its "
        f"first touch-down at t = {first_s:.4g} s ends at {first_s + period_s:.4g} s, after its "
        f"last sample at {t_s[-1]:.4g} s (log at least one more period)"
    )


def leg_energy(
    leg: str,
    t_s: np.ndarray,
    mechanical_w: np.ndarray,
    loss_w: np.ndarray,
    stance: np.ndarray,
    windows_s: list[tuple[float, float]],
) -> LegEnergy:
    """A leg's energies over complete cycles from its sampled powers (every window at once).

    Args:
        leg: Leg name.
        t_s: Sample times, shape (n,) [s].
        mechanical_w: Mechanical power ``sum |tau qd|`` over the leg's joints, shape (n,) [W].
        loss_w: What the drives draw beyond it (SCalf: the friction heat), shape (n,) [W].
        stance: Whether each sample is in stance, shape (n,).
        windows_s: The complete cycles ``(start, end)`` [s].
    """
    ends = np.array(windows_s)  # every window at once: linear in the log's length
    count = len(windows_s)
    per_phase = {
        name: float(window_integrals(t_s, mechanical_w * mask, ends).sum()) / count
        for name, mask in (("stance", stance), ("swing", ~stance))
    }
    return LegEnergy(
        leg=leg,
        windows_s=windows_s,
        mechanical_j={**per_phase, "cycle": per_phase["stance"] + per_phase["swing"]},
        per_cycle_j=[float(e) for e in window_integrals(t_s, mechanical_w, ends)],
        friction_heat_j=float(window_integrals(t_s, loss_w, ends).sum()) / count,
    )


@dataclass(frozen=True)
class LogAnalysis:
    """The energy in a log.

    Attributes:
        source: The log.
        period_s: Gait period used [s].
        period_source: Where it came from (``--period``, ``contact``, ``gait``).
        duty_cycle: The duty cycle of the trot schedule the phases come from (``None`` when
            they come from the log's contact column).
        sample_rate_hz: Median sample rate of the log [Hz].
        half_window_s: Half-width of the derivative filter's window [s].
        degree: Degree of the derivative filter's polynomial.
        legs: Per leg in the log, its energies.
    """

    source: str
    period_s: float
    period_source: str
    sample_rate_hz: float
    half_window_s: float
    degree: int
    legs: dict[str, LegEnergy]
    duty_cycle: float | None = None

    @property
    def phase_source(self) -> str:
        """Where the phases come from: ``contact`` (the log's column) or ``schedule``."""
        return "contact" if self.duty_cycle is None else "schedule"

    @property
    def average_power_w(self) -> float:
        """The legs' mean mechanical energy per cycle over the period [W]."""
        return sum(e.mechanical_j["cycle"] for e in self.legs.values()) / self.period_s

    @property
    def average_total_power_w(self) -> float:
        """The same with the cylinders' friction heat, as the model charges it [W]."""
        heat = sum(e.friction_heat_j for e in self.legs.values())
        return self.average_power_w + heat / self.period_s

    def as_dict(self) -> dict[str, Any]:
        """Plain data for ``--json``."""
        return {
            "source": self.source,
            "period_s": self.period_s,
            "period_source": self.period_source,
            "phase_source": self.phase_source,
            "duty_cycle": self.duty_cycle,
            "sample_rate_hz": self.sample_rate_hz,
            "filter": {
                "kind": "local least-squares polynomial (Savitzky-Golay) on the time stamps",
                "degree": self.degree,
                "window_s": 2 * self.half_window_s,
                "samples": 2
                * half_window_samples(self.sample_rate_hz, self.half_window_s, self.degree)
                + 1,
            },
            "legs": list(self.legs),
            "complete_cycles": {leg: len(e.windows_s) for leg, e in self.legs.items()},
            "mechanical_energy_per_cycle_j": {
                leg: e.mechanical_j["cycle"] for leg, e in self.legs.items()
            },
            "mechanical_energy_per_phase_j": {
                leg: {"stance": e.mechanical_j["stance"], "swing": e.mechanical_j["swing"]}
                for leg, e in self.legs.items()
            },
            "mechanical_energy_of_each_cycle_j": {
                leg: e.per_cycle_j for leg, e in self.legs.items()
            },
            "friction_heat_per_cycle_j": {leg: e.friction_heat_j for leg, e in self.legs.items()},
            "average_power_w": self.average_power_w,
            "average_total_power_w": self.average_total_power_w,
        }


def window_integrals(t_s: np.ndarray, values: np.ndarray, windows: np.ndarray) -> np.ndarray:
    """Integrals of the piecewise-linear interpolant of ``values`` over windows [unit s].

    ``windows`` has a ``[start, end]`` row per window, shape (k, 2).

    One cumulative sum of the trapezoids and a binary search per window end: linear in the
    log's length, whatever the number of windows. The ends must lie inside
    ``[t_s[0], t_s[-1]]``.
    """
    t = np.asarray(t_s, dtype=float)
    p = np.asarray(values, dtype=float)
    cumulative = np.concatenate([[0.0], np.cumsum(0.5 * (p[1:] + p[:-1]) * np.diff(t))])
    ends = np.asarray(windows, dtype=float).reshape(-1, 2)
    k = np.clip(np.searchsorted(t, ends, side="right") - 1, 0, t.size - 2)
    px = np.interp(ends, t, p)
    primitive = cumulative[k] + 0.5 * (p[k] + px) * (ends - t[k])
    return primitive[:, 1] - primitive[:, 0]


def window_integral(t_s: np.ndarray, values: np.ndarray, start: float, end: float) -> float:
    """Integral over ``[start, end]`` of the piecewise-linear interpolant of ``values`` [unit s].

    ``start`` and ``end`` must lie inside ``[t_s[0], t_s[-1]]``.
    """
    return float(window_integrals(t_s, values, np.array([[start, end]]))[0])


POWER_BLOCK_SAMPLES = 8192
"""Samples charged by one call of the model's power function (mapped once over a block: the
time stays linear in the log's length, where one map over the whole log grows faster)."""


def charged_power(
    pipeline: EnergyPipeline, leg: str, theta: np.ndarray, theta_dot: np.ndarray, tau: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """The legs' charged power and drive losses summed over the joints, shape (n,) each [W]."""
    fn = pipeline.physics(leg).power_function("paper").map(POWER_BLOCK_SAMPLES)
    n = theta.shape[1]
    power, loss = np.empty(n), np.empty(n)
    for first in range(0, n, POWER_BLOCK_SAMPLES):
        last = min(first + POWER_BLOCK_SAMPLES, n)
        pad = POWER_BLOCK_SAMPLES - (last - first)
        block = [
            np.pad(a[:, first:last], ((0, 0), (0, pad)), mode="edge")
            for a in (theta, theta_dot, tau)
        ]
        p, q = (np.array(v).sum(axis=0)[: last - first] for v in fn(*block))
        power[first:last], loss[first:last] = p, q
    return power, loss


def leg_cylinders(
    pipeline: EnergyPipeline, leg: str
) -> tuple[HydraulicCylinder, HydraulicCylinder]:
    """The (hip pitch, knee) cylinders of ``leg``.

    Raises:
        LogError: A joint of the leg has no hydraulic cylinder.
    """
    drives = pipeline.physics(leg).drives
    for drive in drives:
        if not isinstance(drive, HydraulicCylinder):
            raise LogError(
                f"robot {pipeline.robot.name}: joint {drive.joint_name} of leg {leg} has no "
                "hydraulic cylinder (no actuator sidecar entry): a cylinder log needs one per "
                "hip pitch and knee"
            )
    return drives[0], drives[1]  # type: ignore[return-value]


def _check_stroke(
    source: str,
    pipeline: EnergyPipeline,
    leg: str,
    data: LegLog,
    cylinders: tuple[HydraulicCylinder, HydraulicCylinder],
) -> None:
    model_leg = pipeline.robot.leg(leg)
    for j, cylinder in enumerate(cylinders):
        lo, hi = cylinder.stroke_limits_m(
            float(model_leg.lower_limits_rad[j]), float(model_leg.upper_limits_rad[j])
        )
        outside = (data.length_m[j] < lo - STROKE_TOLERANCE_M) | (
            data.length_m[j] > hi + STROKE_TOLERANCE_M
        )
        if outside.any():
            k = int(np.flatnonzero(outside)[0])
            raise LogError(
                f"{source}: row {data.rows[k]}, column {LENGTH_COLUMNS[j]}: "
                f"{float(data.length_m[j][k])!r} m is outside the {leg} {JOINT_ROLES[j]} "
                f"cylinder's stroke [{lo:.5f}, {hi:.5f}] m"
            )


def touchdowns(contact: np.ndarray, t_s: np.ndarray) -> np.ndarray:
    """Times of the 0 -> 1 transitions of ``contact`` [s]."""
    rising = np.flatnonzero(contact[1:] & ~contact[:-1]) + 1
    return t_s[rising]


def _period(log: CylinderLog, period_s: float | None, gait_period_s: float) -> tuple[float, str]:
    if period_s is not None:
        return period_s, "--period"
    intervals = [
        np.diff(touchdowns(d.contact, d.t_s)) for d in log.legs.values() if d.contact is not None
    ]
    if intervals and np.concatenate(intervals).size:
        return float(np.median(np.concatenate(intervals))), "contact"
    return gait_period_s, "gait"


def analyze_log(
    log: CylinderLog,
    pipeline: EnergyPipeline,
    period_s: float | None = None,
    half_window_s: float = DEFAULT_HALF_WINDOW_S,
    degree: int = DEFAULT_DEGREE,
) -> LogAnalysis:
    """Energies of every leg in ``log`` (module docstring).

    Args:
        log: The log.
        pipeline: The robot (its cylinders, joint limits and power formula) and the gait (its
            period and duty cycle, used where the log does not say).
        period_s: The gait period [s], overriding the log's contacts and the gait.
        half_window_s: Half-width of the derivative's fitted window [s].
        degree: Degree of the fitted polynomial.

    Raises:
        LogError: A length outside the cylinder's stroke, a leg without cylinders, a log
            shorter than one cycle (the message names the row and the column).
    """
    gait = pipeline.gait
    period, period_source = _period(log, period_s, gait.period_s)
    legs = {}
    for leg, data in log.legs.items():
        cylinders = leg_cylinders(pipeline, leg)
        _check_stroke(log.source, pipeline, leg, data, cylinders)
        t = data.t_s
        where = f"{log.source}: row {data.rows[-1]}, column {TIME}"
        stance, windows = cycle_windows(t, data.contact, gait, leg, period, where)
        half = half_window_samples(1.0 / float(np.median(np.diff(t))), half_window_s, degree)
        if t.size < 2 * half + 1:
            raise LogError(
                f"{log.source}: row {data.rows[-1]}, column {TIME}: leg {leg} has {t.size} "
                f"samples, fewer than the velocity filter's {2 * half + 1}"
            )
        theta = np.vstack(
            [
                np.array(c.angle_from_length_rad(data.length_m[j])).ravel()
                for j, c in enumerate(cylinders)
            ]
        )
        arm = np.vstack(
            [np.array(c.moment_arm_m(theta[j])).ravel() for j, c in enumerate(cylinders)]
        )
        velocity = local_polynomial_derivative(t, data.length_m, half, degree)
        qd, tau = velocity / arm, data.force_n * arm
        drawn, _ = charged_power(pipeline, leg, theta, qd, tau)
        # sum |F v| of the cylinders, whatever the drives charge (a valve-controlled cylinder
        # meters its own input power: drawn minus its losses would be zero)
        mechanical = np.abs(tau * qd).sum(axis=0)
        legs[leg] = leg_energy(leg, t, mechanical, drawn - mechanical, stance, windows)
    steps = np.concatenate([np.diff(d.t_s) for d in log.legs.values()])
    return LogAnalysis(
        source=log.source,
        period_s=period,
        period_source=period_source,
        sample_rate_hz=float(1.0 / np.median(steps)),
        half_window_s=half_window_s,
        degree=degree,
        legs=legs,
        duty_cycle=None if log.has_contact else gait.duty_cycle,
    )
