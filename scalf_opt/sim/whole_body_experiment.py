"""The 3-D referee's runs: a plan at one setting, the ensemble, and ``simulation.json``.

The plan is a saved 3-D cycle (:class:`SavedCycle`) or a sagittal plan (:class:`SagittalTrot`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import mujoco

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.energy.swings import SwingChoice, planned_cycle
from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.energy.whole_body_plan import WholeBodyPlan
from scalf_opt.io.whole_body_export import read_cycle, saved_plan
from scalf_opt.locomotion.contact_schedule import DEFAULT_FRICTION
from scalf_opt.model.robot import Robot
from scalf_opt.sim.ensemble import run_members, with_ensemble_verdicts
from scalf_opt.sim.sagittal_cycle import sagittal_cycle_plan
from scalf_opt.sim.settings import SimSettings
from scalf_opt.sim.whole_body_control import TRUNK_BANDWIDTH_OVER_SERVO
from scalf_opt.sim.whole_body_metrics import cycle_run_summary
from scalf_opt.sim.whole_body_run import WholeBodyRecord, follow_plan
from scalf_opt.types import LEG_NAMES, Accounting


@dataclass(frozen=True)
class SavedCycle:
    """A 3-D cycle saved by ``optimize --model 3d --out DIR``: the plan the referee follows.

    Attributes:
        directory: The cycle's directory.
    """

    directory: str

    def plan(self, physics: WholeBodyPhysics) -> tuple[WholeBodyPlan, dict[str, Any]]:
        """The plan, and what ``simulation.json`` says of where it came from."""
        saved = read_cycle(Path(self.directory))
        return saved_plan(saved, physics), {
            "source": self.directory,
            "plan": "3-D cycle",
            "friction": float(saved.summary["friction"]),
        }


@dataclass(frozen=True)
class SagittalTrot:
    """A sagittal plan (the pipeline's gait and loads, and the swings) as a 3-D plan.

    Attributes:
        pipeline: The sagittal energy model.
        swings: Every leg's swing.
        source: Where the swings come from (``None``: the reference), for ``simulation.json``.
    """

    pipeline: EnergyPipeline
    swings: dict[str, SwingChoice]
    source: str | None = None

    def plan(self, physics: WholeBodyPhysics) -> tuple[WholeBodyPlan, dict[str, Any]]:
        """The plan (:func:`~scalf_opt.sim.sagittal_cycle.sagittal_cycle_plan`), and its origin.

        The origin holds the sagittal model's own energy per leg beside the 3-D model's.
        """
        plan = sagittal_cycle_plan(self.pipeline, self.swings, physics)
        cycle = planned_cycle(self.pipeline, self.swings)
        return plan, {
            "source": self.source,
            "plan": "sagittal",
            "loads": self.pipeline.loads,
            "friction": DEFAULT_FRICTION,
            "sagittal_model_energy_per_cycle_j": {
                leg: float(cycle.legs[leg].energy_j) for leg in LEG_NAMES
            },
        }


@dataclass(frozen=True)
class CycleReferee:
    """One referee's work on a 3-D plan, at the referee's settings.

    It pickles (plain data: the robot and where the plan comes from), so that a worker process
    can run an ensemble's member (:func:`~scalf_opt.sim.ensemble.run_members`); each process
    rebuilds the 3-D model and the plan itself.

    Attributes:
        robot: The robot.
        source: The plan: a :class:`SavedCycle` or a :class:`SagittalTrot`.
        cycles: Gait cycles to simulate (the first is the start-up).
        accounting: The power accounting of both sides of the comparison.
    """

    robot: Robot
    source: SavedCycle | SagittalTrot
    cycles: int
    accounting: Accounting

    def __call__(self, settings: SimSettings) -> dict[str, Any]:
        """The referee's ``simulation.json`` content at ``settings`` (an ensemble member's)."""
        return self.run(settings)[0]

    def run(self, settings: SimSettings) -> tuple[dict[str, Any], WholeBodyRecord]:
        """The referee's ``simulation.json`` content at ``settings``, and its record."""
        physics = WholeBodyPhysics.of(self.robot)
        plan, origin = self.source.plan(physics)
        friction = float(origin.pop("friction"))
        complete, derivation = settings.for_leg_length(self.robot.leg_length_m)
        record, sim, gains = follow_plan(plan, complete, self.cycles, friction)
        data: dict[str, Any] = {
            **origin,
            "model": "3d",
            "mujoco_version": mujoco.__version__,
            "gait": {
                "period_s": plan.schedule.period_s,
                "duty_cycle": plan.schedule.duty_cycle,
                "speed_m_s": plan.speed_m_s,
                "stride_m": plan.stride_m,
                "nodes": plan.schedule.intervals,
            },
            "accounting": self.accounting,
            "cycles": self.cycles,
            "settings": complete.to_dict(),
            "settings_derivation": derivation,
            "controller": {
                "joint_kp_nm_per_rad": dict(zip(physics.joint_names, gains.joint_kp, strict=True)),
                "joint_kd_nms_per_rad": dict(zip(physics.joint_names, gains.joint_kd, strict=True)),
                "trunk_bandwidth_hz": gains.trunk_omega_rad_s / (2 * math.pi),
                "trunk_bandwidth_derivation": f"{TRUNK_BANDWIDTH_OVER_SERVO:g} times the servo's",
                "trunk_damping_ratio": gains.trunk_damping_ratio,
                "friction_pyramid": gains.friction,
                "foot_placement_s": gains.placement_time_s,
                "foot_placement_derivation": "sqrt(h / g), h the plan's mean trunk height",
            },
            "model_repairs": list(sim.repairs),
            **cycle_run_summary(record, plan, self.accounting, self.robot.name),
        }
        return data, record


def cycle_simulation_file(
    referee: CycleReferee,
    settings: SimSettings,
    ensemble: bool = True,
    workers: int | None = None,
) -> tuple[dict[str, Any], WholeBodyRecord]:
    """The content of ``simulation.json`` for a 3-D cycle, and the nominal referee's record.

    With ``ensemble`` every member of :data:`~scalf_opt.sim.ensemble.ENSEMBLE` referees the
    plan and the verdict is their median with its spread
    (:func:`~scalf_opt.sim.ensemble.with_ensemble_verdicts`), the members side by side on
    ``workers`` processes.
    """
    if not ensemble:
        return referee.run(settings)
    nominal: list[tuple[dict[str, Any], WholeBodyRecord]] = []

    def run_nominal() -> dict[str, Any]:
        nominal.append(referee.run(settings))
        return nominal[0][0]

    derived, _ = settings.for_leg_length(referee.robot.leg_length_m)
    runs = run_members(referee, run_nominal, settings, derived, workers=workers)
    data, record = nominal[0]
    goal = float(data["goals"]["joint_energy_relative_difference_at_most"])
    return with_ensemble_verdicts(data, runs, goal), record
