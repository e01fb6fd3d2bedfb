"""A log's energy with measured speeds, its period from the motion, and the plan beside it.

:func:`analyze_measured` extends :func:`~scalf_opt.logs.analysis.analyze_log` (which checks the
log, finds the cycles and phases and differentiates the lengths) where a log knows more:

* speeds: when every leg's cylinder speeds were logged (a bag's ``velocity``, the export's
  speed columns), the mechanical power ``sum |F v|`` takes them as they are, with no filter
  (else the analysis's filter differentiates the lengths); the windows, phases and stroke
  checks stay the analysis's own;
* the period: a log without contact (a bag) and without ``--period`` gets the period of its
  motion: the lag ``T`` at which every cylinder length best repeats itself
  (:func:`motion_period_s`), rather than assuming the gait's;
* the plan: per leg the planned mechanical energy per cycle beside the measured one, and the
  robot's mechanical power over one cycle, measured (mean over the complete cycles, folded on
  the period from the trot's schedule origin) against planned, for the figure.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.trot import stance_start_s
from scalf_opt.logs.analysis import (
    LegEnergy,
    LogAnalysis,
    analyze_log,
    charged_power,
    leg_cylinders,
)
from scalf_opt.logs.analysis import window_integrals as integrals
from scalf_opt.logs.derivative import (
    DEFAULT_DEGREE,
    DEFAULT_HALF_WINDOW_S,
    half_window_samples,
    local_polynomial_derivative,
)
from scalf_opt.logs.joint_log import period_of_motion_s
from scalf_opt.logs.log_file import CylinderLog, LegLog

FOLD_BINS = 200
"""Points of the folded power curve over one cycle."""


@dataclass(frozen=True)
class MeasuredAnalysis:
    """A log's energies and what the log itself told about them.

    Attributes:
        analysis: The energies (with the measured speeds when the log has them).
        velocity_source: ``measured`` (the log's speeds) or ``filter`` (the lengths
            differentiated).
        power_w: Per leg, the sample times [s] and the mechanical power ``|F v|`` [W].
    """

    analysis: LogAnalysis
    velocity_source: str
    power_w: dict[str, tuple[np.ndarray, np.ndarray]]

    def folded_power_w(self, bins: int = FOLD_BINS) -> tuple[np.ndarray, np.ndarray]:
        """The robot's mechanical power over one cycle: cycle times [s] and the mean [W].

        Each leg's power, interpolated at ``bins`` points of each complete cycle of that leg's
        windows, is averaged over its cycles and placed at its cycle time (``t mod T``, the
        schedule's origin); the legs' curves are summed.
        """
        period = self.analysis.period_s
        phase = np.arange(bins) * period / bins
        total = np.zeros(bins)
        for leg, (t, power) in self.power_w.items():
            windows = self.analysis.legs[leg].windows_s
            curves = [np.interp(a + phase, t, power) for a, _ in windows]
            start = windows[0][0] % period
            mean = np.mean(curves, axis=0)
            # sample k of the mean is at cycle time start + phase_k
            total += np.interp(phase, np.mod(start + phase, period), mean, period=period)
        return phase, total


def leg_mechanical_power_w(
    pipeline: EnergyPipeline,
    leg: str,
    data: LegLog,
    speed_m_s: np.ndarray | None,
    half_window_s: float = DEFAULT_HALF_WINDOW_S,
    degree: int = DEFAULT_DEGREE,
) -> tuple[np.ndarray, np.ndarray]:
    """Mechanical power ``sum_j |F_j v_j|`` and the drives' loss rate [W] of each sample, (n,).

    ``speed_m_s`` [m/s] when given, else the lengths' derivative by the analysis's filter. The
    loss rate is what the drives' model draws at that state beyond the joints' mechanical power
    (angle from the length, torque and rate through the moment arm: SCalf's cylinder friction
    heat, a valve-controlled cylinder's throttling), as the analysis charges it.
    """
    cylinders = leg_cylinders(pipeline, leg)
    t = data.t_s
    theta = np.vstack(
        [
            np.array(c.angle_from_length_rad(data.length_m[j])).ravel()
            for j, c in enumerate(cylinders)
        ]
    )
    arm = np.vstack([np.array(c.moment_arm_m(theta[j])).ravel() for j, c in enumerate(cylinders)])
    if speed_m_s is None:
        half = half_window_samples(1.0 / float(np.median(np.diff(t))), half_window_s, degree)
        speed_m_s = local_polynomial_derivative(t, data.length_m, half, degree)
    theta_dot, tau = speed_m_s / arm, data.force_n * arm
    drawn, _ = charged_power(pipeline, leg, theta, theta_dot, tau)
    # beyond the joints' mechanical power, as the log analysis charges it: a valve-controlled
    # cylinder's whole draw (supply pressure x flow) is its "loss", which |F v| would count twice
    return np.abs(data.force_n * speed_m_s).sum(axis=0), drawn - np.abs(tau * theta_dot).sum(axis=0)


def _stance_mask(log_leg: LegLog, pipeline: EnergyPipeline, leg: str, period_s: float) -> Any:
    if log_leg.contact is not None:
        return log_leg.contact
    gait = pipeline.gait
    offset = stance_start_s(gait, leg) * period_s / gait.period_s
    return np.mod(log_leg.t_s - offset, period_s) < gait.duty_cycle * period_s


def motion_period_s(log: CylinderLog) -> float:
    """The period of the legs' motion [s], from their cylinder lengths.

    See :func:`~scalf_opt.logs.joint_log.period_of_motion_s`.

    Raises:
        LogError: The log is too short to hold two periods, or its motion is not periodic.
    """
    series = [(d.t_s, d.length_m) for d in log.legs.values()]
    return period_of_motion_s(log.source, series)


def analyze_measured(
    log: CylinderLog,
    pipeline: EnergyPipeline,
    period_s: float | None = None,
    half_window_s: float = DEFAULT_HALF_WINDOW_S,
    degree: int = DEFAULT_DEGREE,
) -> MeasuredAnalysis:
    """The log's energies, with its speeds and its motion's period (module docstring).

    Raises:
        LogError: Everything :func:`~scalf_opt.logs.analysis.analyze_log` refuses; a log without
            contact too short or not periodic enough to find its period.
    """
    from_motion = period_s is None and not log.has_contact
    if from_motion:
        period_s = motion_period_s(log)
    analysis = analyze_log(log, pipeline, period_s, half_window_s, degree)
    if from_motion:
        analysis = replace(analysis, period_source="motion")
    speeds = {leg: getattr(d, "speed_m_s", None) for leg, d in log.legs.items()}
    measured = all(s is not None for s in speeds.values())
    # the energies of the power series below: with the filter, the analysis's own on a
    # cylinder-charging robot (SCalf, to round-off: tests/logs/test_bags.py), and |F v| too on
    # one whose drives charge no joint power (HyQ's valve-controlled cylinders)
    power: dict[str, tuple[np.ndarray, np.ndarray]] = {}
    legs: dict[str, LegEnergy] = {}
    for leg, data in log.legs.items():
        mechanical, loss = leg_mechanical_power_w(
            pipeline, leg, data, speeds[leg] if measured else None, half_window_s, degree
        )
        power[leg] = (data.t_s, mechanical)
        old = analysis.legs[leg]
        windows = old.windows_s
        stance = _stance_mask(data, pipeline, leg, analysis.period_s)
        count = len(windows)
        ends = np.array(windows)  # every window at once: linear in the log's length
        per_phase = {
            name: float(integrals(data.t_s, mechanical * mask, ends).sum()) / count
            for name, mask in (("stance", stance), ("swing", ~stance))
        }
        legs[leg] = LegEnergy(
            leg=leg,
            windows_s=windows,
            mechanical_j={**per_phase, "cycle": per_phase["stance"] + per_phase["swing"]},
            per_cycle_j=[float(e) for e in integrals(data.t_s, mechanical, ends)],
            friction_heat_j=float(integrals(data.t_s, loss, ends).sum()) / count,
        )
    analysis = replace(analysis, legs=legs)
    return MeasuredAnalysis(analysis, "measured" if measured else "filter", power)


@dataclass(frozen=True)
class PlanComparison:
    """The plan a log should have followed: its energies and its power over one cycle.

    Attributes:
        source: The plan's ``summary.json``.
        period_s: The plan's period [s].
        mechanical_j: Per leg, the planned mechanical energy ``sum |tau qd|`` per cycle [J].
        t_s: Cycle times of the planned power, shape (n,) [s] (0: RF touches down).
        power_w: The robot's planned mechanical power at ``t_s`` [W].
    """

    source: str
    period_s: float
    mechanical_j: dict[str, float]
    t_s: np.ndarray
    power_w: np.ndarray

    @property
    def average_power_w(self) -> float:
        """The plan's mechanical average power [W]."""
        return sum(self.mechanical_j.values()) / self.period_s

    def compare(self, analysis: LogAnalysis) -> dict[str, Any]:
        """Plain data: per leg in the log, measured and planned energy and their change [%]."""
        legs = {}
        for leg, energy in analysis.legs.items():
            planned = self.mechanical_j[leg]
            measured = energy.mechanical_j["cycle"]
            legs[leg] = {
                "measured_j": measured,
                "planned_j": planned,
                "change_percent": 100.0 * (measured - planned) / planned,
            }
        measured_w = sum(v["measured_j"] for v in legs.values()) / analysis.period_s
        planned_w = sum(v["planned_j"] for v in legs.values()) / self.period_s
        return {
            "plan": self.source,
            "legs": legs,
            "measured_average_power_w": measured_w,
            "planned_average_power_w": planned_w,
            "change_percent": 100.0 * (measured_w - planned_w) / planned_w,
        }


def plan_comparison(export: Any) -> PlanComparison:
    """The comparison data of a one-cycle :class:`~scalf_opt.io.plan_export.PlanExport`."""
    from scalf_opt.io.plan_export import planned_mechanical_energy_j

    power = sum(np.abs(v["tau"] * v["qd"]).sum(axis=0) for v in export.values.values())
    return PlanComparison(
        str(export.saved.source),
        export.saved.gait.period_s,
        planned_mechanical_energy_j(export.cycle),
        export.t_s,
        np.asarray(power, dtype=float),
    )
