"""``simulate``: the planned trot in MuJoCo (extra ``sim``), beside the model's prediction."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from scalf_opt.api.gaits import as_robot, read_gait
from scalf_opt.energy.loads import DEFAULT_LOADS
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import ConfigError, LogError
from scalf_opt.files import write_atomic
from scalf_opt.io.provenance import provenance
from scalf_opt.io.results import to_json
from scalf_opt.locomotion.gait import Gait
from scalf_opt.model.robot import Robot
from scalf_opt.types import Accounting

JOINT_STATE_RATE_HZ = 1000.0
"""Rate of a simulation bag's ``/joint_states`` [Hz] (a joint driver's usual rate)."""

MAX_SIM_CYCLES = 200
"""Most gait cycles one simulation may run (about 10 minutes of MuJoCo on one core)."""


@dataclass(frozen=True)
class _Simulated:
    """What every simulation gives: the robot, ``simulation.json``, the record and a title.

    Attributes:
        robot: The robot.
        data: ``simulation.json`` (the subclass says what is in it).
        record: The step-by-step record.
        title: A one-line description, for reports and the figure.
    """

    robot: Robot
    data: dict[str, Any]
    record: Any
    title: str

    def to_dict(self) -> dict[str, Any]:
        """Plain data: ``simulation.json``."""
        return self.data


@dataclass(frozen=True)
class SimulationResult(_Simulated):
    """A MuJoCo simulation of the planned trot (extra ``sim``), beside the model's prediction.

    ``data`` holds provenance, settings and every figure (:mod:`scalf_opt.sim.metrics`), with
    ``reference`` and ``saving_vs_reference`` when the swings are not the reference; ``record``
    is a :class:`scalf_opt.sim.run.SimRecord`.
    """

    def figure(self) -> Any:
        """The figure of ``simulation.png`` (a matplotlib ``Figure``)."""
        from scalf_opt.viz.simulation_figure import simulation_figure

        record = self.record
        return simulation_figure(
            record.t_s,
            record.trunk[1],
            record.start_trunk_height_m,
            record.trunk[2],
            {leg: force[1] for leg, force in record.grf_n.items()},
            float(self.data["model_stance_force_mean_n"]["RF"]),
            self.title,
            startup_s=float(self.data["gait"]["period_s"]),
            phase_energy_j=self.data["joint_energy_per_phase_j"],
            energy_goal=float(self.data["goals"]["joint_energy_relative_difference_at_most"]),
            fell_at_s=self.data.get("fell_at_s"),
            diverged_at_s=record.diverged_at_s,
            divergence=record.divergence,
        )

    def write(self, out_dir: str | Path) -> list[Path]:
        """Write ``simulation.json``, ``simulation.png`` and ``report.txt`` into ``out_dir``.

        ``report.txt`` is the whole report (the command prints its summary); each file is
        written atomically.
        """
        from scalf_opt.sim.report import simulation_report
        from scalf_opt.viz.figures import save_atomic

        out, figure = Path(out_dir), self.figure()
        return [
            write_atomic(out / "simulation.json", to_json(self.data)),
            save_atomic(figure, out / "simulation.png"),
            write_atomic(out / "report.txt", simulation_report(self.data, self.title) + "\n"),
        ]

    def write_log(self, path: str | Path, seed: int = 0) -> Path:
        """Write the log of the run: the cylinder CSV, or with ``.mcap`` a ROS 2 bag.

        The CSV (and the bag's ``/cylinder_states``) is what SCalf's sensors would record
        (80 Hz, 0.1 mm, 70 N). The bag has ``/joint_states``: every joint's angle, rate and
        torque at 1 kHz, the joint-state topic a ROS 2 driver publishes (the rate is the joint's
        over the simulation step that follows, so that ``tau qd`` is that step's power); a robot
        without cylinders has only that topic.

        Raises:
            LogError: A CSV of a robot whose legs have no hydraulic cylinders.
        """
        from scalf_opt.logs.analysis import leg_cylinders
        from scalf_opt.logs.log_file import log_csv_text

        pipeline = EnergyPipeline(self.robot, read_gait(robot=self.robot))
        if Path(path).suffix == ".mcap":
            try:
                cylinders = {leg: leg_cylinders(pipeline, leg) for leg in self.record.q_rad}
            except LogError:
                return self._write_bag(Path(path), None)
            return self._write_bag(Path(path), self._sensor_log(cylinders, seed, str(path)))
        cylinders = {leg: leg_cylinders(pipeline, leg) for leg in self.record.q_rad}
        return write_atomic(path, log_csv_text(self._sensor_log(cylinders, seed, str(path))))

    def _sensor_log(self, cylinders: dict[str, Any], seed: int, source: str) -> Any:
        """What SCalf's cylinder sensors would record of the run."""
        from scalf_opt.logs.sensors import JointMotion, SensorModel, sensor_log

        record = self.record
        motions = {
            leg: JointMotion(
                record.t_s, record.q_rad[leg], record.tau_nm[leg], record.in_contact(leg)
            )
            for leg in cylinders
        }
        return sensor_log(motions, cylinders, SensorModel(), seed, source)

    def _write_bag(self, path: Path, log: Any) -> Path:
        from scalf_opt.io.ros_bag import JointStateSeries, cylinder_joint_name, write_bag

        record = self.record
        stride = max(1, round(1.0 / (JOINT_STATE_RATE_HZ * record.timestep_s)))
        legs = list(record.q_rad)
        names = tuple(n for leg in legs for n in self.robot.leg(leg).joint_names)
        series = [
            JointStateSeries(
                "/joint_states",
                names,
                record.t_s[::stride],
                np.vstack([record.q_rad[leg][:, ::stride] for leg in legs]),
                np.vstack([record.qd_rad_s[leg][:, ::stride] for leg in legs]),
                np.vstack([record.tau_nm[leg][:, ::stride] for leg in legs]),
            )
        ]
        if log is not None:
            first = log.legs[legs[0]]  # the sensors sample every leg at the same instants
            series.append(
                JointStateSeries(
                    "/cylinder_states",
                    tuple(cylinder_joint_name(n) for n in names),
                    first.t_s,
                    np.vstack([log.legs[leg].length_m for leg in legs]),
                    None,
                    np.vstack([log.legs[leg].force_n for leg in legs]),
                )
            )
        return write_bag(path, series)


def _check_cycles(cycles: int) -> None:
    """Refuse a cycle count outside 2..:data:`MAX_SIM_CYCLES` (the first is the start-up).

    Raises:
        ConfigError: Naming ``cycles``.
    """
    if isinstance(cycles, bool) or not isinstance(cycles, int) or not 2 <= cycles <= MAX_SIM_CYCLES:
        raise ConfigError(
            f"cycles must be an integer in 2..{MAX_SIM_CYCLES} (the first is the start-up), got "
            f"{cycles!r}",
            field="cycles",
        )


@dataclass(frozen=True)
class _SagittalPlan:
    """A sagittal plan ready to simulate: the robot, its energy model, swings and settings."""

    robot: Robot
    pipeline: EnergyPipeline
    swings: dict[str, Any]
    source: str | None
    settings: Any

    @property
    def families(self) -> str:
        """The swings' families, for titles (``joint-6, reference``)."""
        return ", ".join(sorted({family for family, _ in self.swings.values()}))


def _sagittal_plan(
    robot: str | Robot,
    gait: Gait | None,
    swings_from: str | Path | None,
    cycles: int,
    accounting: Accounting,
    servo_bandwidth_hz: float | None,
    loads: str | None,
) -> _SagittalPlan:
    """The checked inputs of :func:`simulate` and :func:`simulate_3d`, as one plan.

    Raises:
        ConfigError: As :func:`simulate` says.
    """
    from scalf_opt.io.saved import read_saved_swings
    from scalf_opt.sim.plan import REFERENCE_SWINGS
    from scalf_opt.sim.settings import SimSettings

    robot = as_robot(robot)
    _check_cycles(cycles)
    if swings_from is not None and gait is not None:
        raise ConfigError("the gait comes with the swings' summary.json: give one", field="gait")
    settings = (
        SimSettings()
        if servo_bandwidth_hz is None
        else SimSettings(servo_bandwidth_hz=servo_bandwidth_hz)
    )
    if swings_from is not None:
        saved = read_saved_swings(swings_from)
        saved.check_robot(robot)
        gait, swings = saved.gait, saved.require_all_legs()
        loads = loads or saved.loads
    else:
        gait, swings = gait or read_gait(robot=robot), dict(REFERENCE_SWINGS)
    pipeline = EnergyPipeline(robot, gait, accounting, loads=loads or DEFAULT_LOADS)
    source = str(swings_from) if swings_from is not None else None
    return _SagittalPlan(robot, pipeline, dict(swings), source, settings)


def simulate(
    robot: str | Robot,
    gait: Gait | None = None,
    *,
    swings_from: str | Path | None = None,
    cycles: int = 10,
    accounting: Accounting = "paper",
    servo_bandwidth_hz: float | None = None,
    loads: str | None = None,
    ensemble: bool = True,
    command: Sequence[str] | None = None,
) -> SimulationResult:
    """Simulate the planned trot in MuJoCo (needs the ``sim`` extra).

    Args:
        robot: The robot.
        gait: The gait (default: the robot's default trot); not with ``swings_from``.
        swings_from: A folder with the ``summary.json`` of ``optimize_swing(...).write(...)``:
            its swings and gait (its stance included) are simulated, and the reference beside
            them where the reference is possible at that gait (else ``reference_skipped``).
        cycles: Gait cycles to simulate (>= 2; the first is the start-up).
        accounting: Power accounting of the joint energies.
        servo_bandwidth_hz: Natural frequency of the servo's feedback loops [Hz] (default:
            derived from the leg length, 30 Hz on SCalf; :mod:`scalf_opt.sim.settings`).
        loads: The energy model's stance loads (the model's side and the plan's feed-forward):
            ``None`` gives the saved swings' own, else ``whole-body``.
        ensemble: The verdict is the median over the referee ensemble, with its spread
            (:mod:`scalf_opt.sim.ensemble`: ten referees, each simulating plan and reference);
            ``False``: the nominal referee alone.
        command: The command line, recorded in the result's provenance.

    Raises:
        ConfigError: Fewer than 2 cycles, a gait given with ``swings_from``, a bad
            ``summary.json`` or one of another robot, a servo too fast for the time step.
    """
    from scalf_opt.sim.experiment import simulation_file

    p = _sagittal_plan(robot, gait, swings_from, cycles, accounting, servo_bandwidth_hz, loads)
    data, run = simulation_file(
        p.robot, p.pipeline, p.swings, p.settings, cycles, p.source, ensemble
    )
    data = {"provenance": provenance(p.robot, command), **data}
    title = (
        f"MuJoCo {data['mujoco_version']} simulation of {p.robot.name}, {p.families} swing: "
        f"{p.pipeline.gait.trot_text}, {cycles} cycles, "
        f"dt={1e3 * data['settings']['timestep_s']:g} ms, servo "
        f"{data['settings']['servo_bandwidth_hz']:.3g} Hz"
    )
    return SimulationResult(p.robot, data, run.record, title)


def simulate_3d(
    robot: str | Robot,
    gait: Gait | None = None,
    *,
    swings_from: str | Path | None = None,
    cycles: int = 10,
    accounting: Accounting = "paper",
    servo_bandwidth_hz: float | None = None,
    loads: str | None = None,
    ensemble: bool = True,
    command: Sequence[str] | None = None,
) -> CycleSimulationResult:
    """A sagittal plan in the 3-D referee, the whole robot free (needs the ``sim`` extra).

    The plan (the reference swing, or the swings and gait of ``swings_from``) becomes a 3-D plan
    (:mod:`scalf_opt.sim.sagittal_cycle`: the trunk level at constant height, the abduction joints
    at zero, the minimum-norm stance forces, the moment about the diagonal left unbalanced) and
    the 3-D referee runs it; no reference beside it. The arguments are :func:`simulate`'s.

    Raises:
        ConfigError: As :func:`simulate` says.
    """
    from scalf_opt.sim.whole_body_experiment import (
        CycleReferee,
        SagittalTrot,
        cycle_simulation_file,
    )

    p = _sagittal_plan(robot, gait, swings_from, cycles, accounting, servo_bandwidth_hz, loads)
    trot = SagittalTrot(p.pipeline, p.swings, p.source)
    referee = CycleReferee(p.robot, trot, cycles, p.pipeline.accounting)
    data, record = cycle_simulation_file(referee, p.settings, ensemble)
    data = {"provenance": provenance(p.robot, command), **data}
    title = (
        f"MuJoCo {data['mujoco_version']} 3-D referee of {p.robot.name}'s sagittal plan, "
        f"{p.families} swing: {p.pipeline.gait.trot_text}, {cycles} cycles, "
        f"dt={1e3 * data['settings']['timestep_s']:g} ms"
    )
    return CycleSimulationResult(p.robot, data, record, title)


@dataclass(frozen=True)
class CycleSimulationResult(_Simulated):
    """A 3-D cycle refereed in MuJoCo (extra ``sim``), beside the plan's own energy.

    ``data`` holds provenance, settings, the controller's gains and every figure
    (:mod:`scalf_opt.sim.whole_body_metrics`), the ensemble's verdict when it ran; ``record`` is
    the nominal referee's :class:`~scalf_opt.sim.whole_body_run.WholeBodyRecord`.
    """

    def figure(self) -> Any:
        """The figure of ``simulation.png`` (a matplotlib ``Figure``)."""
        from scalf_opt.viz.whole_body_sim_figure import cycle_simulation_figure

        r = self.record
        return cycle_simulation_figure(
            r.t_s,
            r.q,
            r.q_plan,
            r.contact_force_n,
            r.plan_force_n,
            r.fell_at_s,
            float(self.data["gait"]["period_s"]),
            self.title,
            diverged_at_s=r.diverged_at_s,
            divergence=r.divergence,
        )

    def write(self, out_dir: str | Path) -> list[Path]:
        """Write ``simulation.json``, ``simulation.png`` and ``report.txt`` (each atomically)."""
        from scalf_opt.sim.whole_body_report import cycle_simulation_report
        from scalf_opt.viz.figures import save_atomic

        out, figure = Path(out_dir), self.figure()
        return [
            write_atomic(out / "simulation.json", to_json(self.data)),
            save_atomic(figure, out / "simulation.png"),
            write_atomic(out / "report.txt", cycle_simulation_report(self.data, self.title) + "\n"),
        ]


def simulate_cycle(
    cycle_from: str | Path,
    robot: str | Robot | None = None,
    *,
    cycles: int = 10,
    accounting: Accounting | None = None,
    servo_bandwidth_hz: float | None = None,
    ensemble: bool = True,
    command: Sequence[str] | None = None,
    workers: int | None = None,
) -> CycleSimulationResult:
    """Referee a saved 3-D cycle in MuJoCo, the whole robot free (needs the ``sim`` extra).

    Args:
        cycle_from: The directory ``optimize --model 3d --out DIR`` wrote.
        robot: The robot (default: the cycle's, from the catalog).
        cycles: Gait cycles to simulate (2..:data:`MAX_SIM_CYCLES`; the first is the start-up).
        accounting: Power accounting of both sides (default: the cycle's own).
        servo_bandwidth_hz: Natural frequency of the swing joints' loops [Hz] (default: derived
            from the leg length; the trunk loop follows, :mod:`scalf_opt.sim.whole_body_control`).
        ensemble: The verdict is the median over the referee ensemble with its spread
            (:mod:`scalf_opt.sim.ensemble`); ``False``: the nominal referee alone.
        command: The command line, recorded in the result's provenance.
        workers: Processes for the ensemble's members (default: one per core).

    Raises:
        ConfigError: Fewer than 2 cycles, a directory that is not a 3-D cycle, a robot other than
            the cycle's, a servo too fast for the time step.
    """
    from scalf_opt.io.whole_body_export import read_cycle
    from scalf_opt.sim.settings import SimSettings
    from scalf_opt.sim.whole_body_experiment import (
        CycleReferee,
        SavedCycle,
        cycle_simulation_file,
    )

    _check_cycles(cycles)
    saved = read_cycle(Path(cycle_from))
    robot = as_robot(robot if robot is not None else str(saved.summary.get("robot")))
    accounting = accounting or saved.summary.get("accounting", "paper")
    settings = (
        SimSettings()
        if servo_bandwidth_hz is None
        else SimSettings(servo_bandwidth_hz=servo_bandwidth_hz)
    )
    referee = CycleReferee(robot, SavedCycle(str(cycle_from)), cycles, accounting)
    data, record = cycle_simulation_file(referee, settings, ensemble, workers)
    data = {"provenance": provenance(robot, command), **data}
    gait = data["gait"]
    title = (
        f"MuJoCo {data['mujoco_version']} referee of {robot.name}'s 3-D cycle {Path(cycle_from)}: "
        f"T={gait['period_s']:.3g} s, duty {gait['duty_cycle']:g}, {gait['speed_m_s']:.3g} m/s, "
        f"{cycles} cycles, dt={1e3 * data['settings']['timestep_s']:g} ms"
    )
    return CycleSimulationResult(robot, data, record, title)
