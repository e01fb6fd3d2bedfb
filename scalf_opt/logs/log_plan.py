"""The model at a log's own gait, joint by joint beside what the robot spent.

From a whole-robot log's analysis (:mod:`~scalf_opt.logs.robot_energy`): the period and duty
factor are the medians of the legs' measured ones, the step length the speed times the stance
time, the stance height the mean height of the pitching hips over their feet in stance (the URDF's
kinematics at the logged angles), the clearance the default trot's. The sagittal model evaluates
the reference trot at that gait (every limit of today; the stance loads of the default load
model), and each joint's planned mechanical energy per cycle ``integral |tau qd|`` is set beside
the measured one, with their ratio; the joints the model leaves out (the abduction) are planned
at nothing. Powers are folded on each leg's cycle, from its touch-down, for the figure.

A flying trot (duty under 0.5) has instants with no foot on the ground, which a trunk on a fixed
line cannot have: the sagittal model is evaluated at duty 0.5, the nearest gait it walks, and the
comparison says so.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from itertools import pairwise
from typing import Any

import numpy as np

from scalf_opt.errors import ConfigError
from scalf_opt.logs.robot_energy import RobotLogAnalysis
from scalf_opt.model.robot import Robot

PHASE_POINTS = 201
"""Points of the folded cycle (phase 0 at touch-down to 1 at the next)."""

MAX_RATE_HZ = 2000.0
"""The model is evaluated at the log's rate, at most this [Hz] (a 1 kHz log's is kept)."""

SAGITTAL_MIN_DUTY = 0.5
"""The least duty factor the sagittal model walks (a foot pair always on the ground)."""


@dataclass(frozen=True)
class JointComparison:
    """One joint's measured and planned energy per cycle [J] and its folded powers [W]."""

    joint: str
    leg: str
    measured_j: float
    planned_j: float
    measured_w: np.ndarray
    planned_w: np.ndarray

    @property
    def ratio(self) -> float | None:
        """Measured over planned, or ``None`` when nothing is planned."""
        return self.measured_j / self.planned_j if self.planned_j > 0 else None


@dataclass(frozen=True)
class LogPlanComparison:
    """The log against the model at its gait (module docstring).

    Attributes:
        gait: The gait the model was evaluated at.
        log_duty_cycle: The log's measured duty factor (the gait's may be 0.5: a flying trot).
        loads: The model's stance load model.
        joints: Per leg joint, the comparison.
        phase: The folded cycle's phase grid, shape (:data:`PHASE_POINTS`,).
        notes: What differs between the log's gait and the model's.
    """

    gait: Any
    log_duty_cycle: float
    loads: str
    joints: tuple[JointComparison, ...]
    phase: np.ndarray
    notes: tuple[str, ...]

    def as_dict(self) -> dict[str, Any]:
        """Plain data for ``--json``."""
        g = self.gait
        return {
            "model": "sagittal",
            "loads": self.loads,
            "gait": {
                "period_s": g.period_s,
                "duty_cycle": g.duty_cycle,
                "step_length_m": g.step_length_m,
                "stance_height_m": g.stance_height_m,
                "clearance_m": g.clearance_m,
            },
            "log_duty_cycle": self.log_duty_cycle,
            "joints": {
                c.joint: {
                    "leg": c.leg,
                    "measured_j": c.measured_j,
                    "planned_j": c.planned_j,
                    "ratio": c.ratio,
                }
                for c in self.joints
            },
            "notes": list(self.notes),
        }


def _fold(t: np.ndarray, values: np.ndarray, starts: np.ndarray, phase: np.ndarray) -> np.ndarray:
    """``values(t)`` averaged over the cycles ``starts[k]..starts[k+1]`` on the phase grid."""
    cycles = [np.interp(a + phase * (b - a), t, values) for a, b in pairwise(starts)]
    return np.mean(cycles, axis=0)


def compare_with_plan(
    analysis: RobotLogAnalysis,
    robot: Robot,
    t_s: np.ndarray,
    power_w: dict[str, np.ndarray],
    foot_height_m: dict[str, np.ndarray],
    stance: dict[str, np.ndarray],
    loads: str | None = None,
) -> LogPlanComparison:
    """Evaluate the model at the log's gait and compare joint by joint (module docstring).

    Args:
        analysis: The log's analysis (its legs' periods, duty factors, speed).
        robot: The robot.
        t_s: The log's sample times [s].
        power_w: Per joint, its measured mechanical power ``|tau qd|`` at the samples [W].
        foot_height_m: Per leg, the foot's height in the leg plane at the samples [m].
        stance: Per leg, its stance samples.
        loads: The model's stance load model (``None``: the default).

    Raises:
        ConfigError: No speed (``--speed`` or an odometry topic): the step length needs it.
        GaitError: The log's gait is outside what the model walks (its message names the field).
    """
    from scalf_opt.energy.loads import DEFAULT_LOADS
    from scalf_opt.energy.physics import trapezoid_weights
    from scalf_opt.energy.pipeline import EnergyPipeline
    from scalf_opt.locomotion.scaling import default_gait_for
    from scalf_opt.locomotion.swing.registry import make_family

    if analysis.speed_m_s is None:
        raise ConfigError(
            "--compare: the model's step length needs the log's speed: give --speed or an "
            "odometry topic (--odometry)",
            field="speed_m_s",
        )
    notes = []
    duty = analysis.duty_cycle
    # a sampled duty factor is uncertain by a sample per cycle: 0.4999 is a walking trot
    resolution = max(1.0 / (analysis.sample_rate_hz * analysis.period_s), 0.005)
    if duty < SAGITTAL_MIN_DUTY - resolution:
        notes.append(
            f"the log's duty factor {duty:.3f} is a flying trot (no foot on the ground for part "
            f"of each cycle), which the sagittal model cannot walk: it is evaluated at duty "
            f"{SAGITTAL_MIN_DUTY}, the nearest gait it walks"
        )
    model_duty = max(duty, SAGITTAL_MIN_DUTY)
    period = analysis.period_s
    heights = [
        float(np.median(robot.leg(leg).hip_origin_m[2] - foot_height_m[leg][stance[leg]]))
        for leg in stance
    ]
    default = default_gait_for(robot)
    gait = replace(
        default,
        # sampled like the log (the energies of |tau qd| are trapezoids at both ends)
        sample_rate_hz=min(max(analysis.sample_rate_hz, default.sample_rate_hz), MAX_RATE_HZ),
        period_s=period,
        duty_cycle=model_duty,
        step_length_m=analysis.speed_m_s * period * model_duty,
        stance_height_m=float(np.mean(heights)),
    )
    pipeline = EnergyPipeline(robot, gait, "paper", loads=loads or DEFAULT_LOADS)
    cycle = pipeline.robot_cycle(make_family("reference"))
    phase = np.linspace(0.0, 1.0, PHASE_POINTS)
    joints = []
    for leg, cycles in analysis.legs.items():
        leg_cycle = cycle.legs[leg]
        modelled = list(robot.leg(leg).joint_names)
        stance_phase, swing_phase = leg_cycle.stance, leg_cycle.swing
        t_plan = np.concatenate(
            [stance_phase.t_phase_s, stance_phase.t_phase_s[-1] + swing_phase.t_phase_s]
        )
        for energy in (j for j in analysis.joints if j.leg == leg):
            measured_w = _fold(t_s, power_w[energy.joint], cycles.touchdowns_s, phase)
            planned_j = 0.0
            planned_w = np.zeros(PHASE_POINTS)
            if energy.joint in modelled:
                row = modelled.index(energy.joint)
                p = [np.abs(ph.values["p_mech"][row]) for ph in (stance_phase, swing_phase)]
                planned_j = float(
                    sum(
                        pp @ trapezoid_weights(ph.t_phase_s)
                        for pp, ph in zip(p, (stance_phase, swing_phase), strict=True)
                    )
                )
                planned_w = np.interp(phase * gait.period_s, t_plan, np.concatenate(p))
            joints.append(
                JointComparison(energy.joint, leg, energy.cycle_j, planned_j, measured_w, planned_w)
            )
    return LogPlanComparison(gait, duty, cycle.loads, tuple(joints), phase, tuple(notes))
