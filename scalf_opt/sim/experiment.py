"""One simulated trot from a plan to its figures, and the simulation's result file."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import mujoco

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import GaitError, InfeasibleError
from scalf_opt.model.robot import Robot
from scalf_opt.sim.control import servo_gains, trunk_gains
from scalf_opt.sim.ensemble import run_members, with_ensemble_verdicts
from scalf_opt.sim.inverse import plan_inverse_dynamics
from scalf_opt.sim.metrics import saving_comparison, summarize
from scalf_opt.sim.mujoco_model import build_sim_model
from scalf_opt.sim.plan import REFERENCE_SWINGS, SwingChoice, TrotPlan, planned_cycle
from scalf_opt.sim.run import SimRecord, simulate
from scalf_opt.sim.settings import SimSettings


@dataclass(frozen=True)
class TrotRun:
    """A simulated trot.

    Attributes:
        result: Its figures (:func:`~scalf_opt.sim.metrics.summarize`), the servo gains and the
            swings, as plain data.
        record: The step-by-step record.
    """

    result: dict[str, Any]
    record: SimRecord


def run_trot(
    robot: Robot,
    pipeline: EnergyPipeline,
    swings: Mapping[str, SwingChoice],
    settings: SimSettings,
    cycles: int,
) -> TrotRun:
    """Plan ``swings`` with ``pipeline``, simulate ``cycles`` cycles and measure them.

    Raises:
        ConfigError, GaitError, InfeasibleError: A swing or gait the pipeline refuses.
        ModelError: MuJoCo cannot build the robot.
    """
    settings, derivation = settings.for_leg_length(robot.leg_length_m)
    model_cycle = planned_cycle(pipeline, swings)
    plan = TrotPlan.build(pipeline, swings, 1.0 / settings.value("timestep_s"))
    sim = build_sim_model(robot, settings)
    gains = servo_gains(robot, plan, settings)
    trunk = trunk_gains(settings) if settings.stance_control == "trunk" else None
    record = simulate(sim, plan, gains, cycles, trunk, settings.schedule_shift_s)
    result = summarize(sim, record, plan, model_cycle, pipeline)
    result["plan_inverse_dynamics"] = plan_inverse_dynamics(
        sim, plan, pipeline, record.timestep_s, record.start_trunk_height_m
    )
    result["settings"] = settings.to_dict()
    result["settings_derivation"] = derivation
    result["model_repairs"] = list(sim.repairs)
    result["servo_gains"] = {
        leg: {"kp_nm_per_rad": g.kp_nm_per_rad, "kd_nms_per_rad": g.kd_nms_per_rad}
        for leg, g in gains.items()
    }
    result["trajectory"] = {
        leg: {"swing_family": family, "swing_parameters": theta}
        for leg, (family, theta) in swings.items()
    }
    return TrotRun(result, record)


def simulation_file(
    robot: Robot,
    pipeline: EnergyPipeline,
    swings: Mapping[str, SwingChoice],
    settings: SimSettings,
    cycles: int,
    source: str | None = None,
    ensemble: bool = True,
    workers: int | None = None,
) -> tuple[dict[str, Any], TrotRun]:
    """The content of ``simulation.json``, and the run it describes.

    ``swings`` are simulated at the pipeline's gait as it is (a saved free stance included). A plan
    that is not the reference is simulated beside the reference at the same gait, and the file
    holds the reference's figures (``reference``) and the saving, simulated and modelled
    (``saving_vs_reference``); when the reference swing is impossible at that gait (a free
    stance that puts its path outside the joint range), the reference is not simulated and
    ``reference_skipped`` says why. With ``ensemble`` every member of
    :data:`~scalf_opt.sim.ensemble.ENSEMBLE` referees plan and reference alike and the verdict
    is their median, the plan's and the reference's
    (:func:`~scalf_opt.sim.ensemble.with_ensemble_verdicts`); the run returned is the nominal
    referee's. The members run side by side on ``workers`` processes (default: one per core;
    :func:`~scalf_opt.sim.ensemble.run_members`), with the same numbers on any number.
    """
    referee = Referee(robot, pipeline, dict(swings), cycles, source)
    if not ensemble:
        return referee.run(settings)
    nominal: list[tuple[dict[str, Any], TrotRun]] = []

    def run_nominal() -> dict[str, Any]:
        nominal.append(referee.run(settings))
        return nominal[0][0]

    derived, _ = settings.for_leg_length(robot.leg_length_m)
    runs = run_members(referee, run_nominal, settings, derived, workers=workers)
    data, run = nominal[0]
    goal = float(data["goals"]["joint_energy_relative_difference_at_most"])
    return with_ensemble_verdicts(data, runs, goal), run


@dataclass(frozen=True)
class Referee:
    """One referee's work: the plan, and the reference beside it, at the referee's settings.

    It pickles (plain data, the robot and the pipeline rebuilding their models where they are
    unpickled), so that a worker process can run an ensemble's member
    (:func:`~scalf_opt.sim.ensemble.run_members`) with the same code as this process.

    Attributes:
        robot: The robot MuJoCo simulates.
        pipeline: The energy model that plans the trot.
        swings: Every leg's swing.
        cycles: Gait cycles to simulate.
        source: Where the swings come from, for ``simulation.json``.
    """

    robot: Robot
    pipeline: EnergyPipeline
    swings: dict[str, SwingChoice]
    cycles: int
    source: str | None = None

    def __call__(self, settings: SimSettings) -> dict[str, Any]:
        """The referee's ``simulation.json`` content at ``settings`` (an ensemble member's)."""
        return self.run(settings)[0]

    def run(self, settings: SimSettings) -> tuple[dict[str, Any], TrotRun]:
        """The referee's ``simulation.json`` content at ``settings``, and the plan's run."""
        return _refereed(self.robot, self.pipeline, self.swings, settings, self.cycles, self.source)


def _refereed(
    robot: Robot,
    pipeline: EnergyPipeline,
    swings: Mapping[str, SwingChoice],
    settings: SimSettings,
    cycles: int,
    source: str | None,
) -> tuple[dict[str, Any], TrotRun]:
    """One referee's ``simulation.json`` content: the plan, and the reference beside it."""
    run = run_trot(robot, pipeline, swings, settings, cycles)
    gait = pipeline.gait
    data: dict[str, Any] = {
        "source": source,
        "mujoco_version": mujoco.__version__,
        "gait": {**gait.to_dict(), "speed_m_s": gait.speed_m_s},
        "accounting": pipeline.accounting,
        "loads": pipeline.loads,
        **run.result,
    }
    if any(family != "reference" for family, _ in swings.values()):
        try:
            reference = run_trot(robot, pipeline, REFERENCE_SWINGS, settings, cycles).result
        except (GaitError, InfeasibleError) as exc:
            data["reference_skipped"] = f"the reference swing is impossible at this gait: {exc}"
        else:
            data["reference"] = reference
            data["saving_vs_reference"] = saving_comparison(run.result, reference)
    return data, run
