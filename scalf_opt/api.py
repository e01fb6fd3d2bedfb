"""The Python API: load a robot, choose a gait, evaluate and optimize, in a few lines.

>>> import scalf_opt as so
>>> robot = so.load_robot("scalf")
>>> result = so.evaluate(robot)            # the cubic-spline reference on the paper's trot
>>> round(result.average_power_w, 2)
564.52

Every result has ``to_dict()``, the same plain data the command line writes to
``summary.json``, and the numbers are the command line's: the ``scalf-opt`` commands call these
functions. (``optimize_swing`` is not called ``optimize``: that name is the package's optimizer
floor, :mod:`scalf_opt.optimize`.)
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import ConfigError
from scalf_opt.files import write_atomic
from scalf_opt.io.provenance import provenance
from scalf_opt.io.results import cycle_summary, samples_csv_text, to_json
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.gait_file import read_gait as read_gait_file
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.model.robot import Robot
from scalf_opt.optimize.pattern_search import PatternSearchOptions
from scalf_opt.optimize.problem import SwingProblem
from scalf_opt.optimize.solve import SwingOptimum
from scalf_opt.optimize.solve import optimize as run_optimizer
from scalf_opt.robots.loading import load_robot
from scalf_opt.studies.paper import Reproduction, reproduce, summary
from scalf_opt.types import FIRST_PAIR, Accounting, Method, check_choice

__all__ = [
    "EvaluationResult",
    "Gait",
    "LogResult",
    "OptimizationResult",
    "PaperResult",
    "SimulationResult",
    "analyze_log",
    "evaluate",
    "load_robot",
    "optimize_swing",
    "paper",
    "read_gait",
    "simulate",
]

Progress = Callable[[str], None]
"""Called with a short label as each step of a long computation starts."""

VERBOSE_IPOPT = {"print_level": 5}

MAX_SIM_CYCLES = 200
"""Most gait cycles one simulation may run (about 10 minutes of MuJoCo on one core)."""
"""Ipopt's own iteration log (``-v`` on the command line)."""


def read_gait(path: str | Path | None = None, robot: Robot | None = None, **fields: float) -> Gait:
    """A gait: the robot's default trot, under a gait file's fields, under ``fields``.

    Args:
        path: A gait file (TOML, ``[gait]`` table); ``None`` for none.
        robot: Whose default gait to start from (the paper's trot scaled to its legs, at its
            stance height, :func:`~scalf_opt.locomotion.scaling.default_gait_for`); ``None``:
            the paper's trot.
        fields: Gait fields to set, e.g. ``period_s=0.4``.

    Raises:
        ConfigError: A bad file or an unknown field.
        GaitError: A value out of range (the message names the file or field).
    """
    unknown = sorted(set(fields) - set(Gait.field_names()))
    if unknown:
        raise ConfigError(
            f"unknown gait field {unknown[0]!r} (known: {', '.join(Gait.field_names())})"
        )
    gait = default_gait_for(robot) if robot is not None else Gait()
    if path is not None:
        gait = read_gait_file(path, gait)
    return replace(gait, **fields) if fields else gait  # type: ignore[arg-type]


@dataclass(frozen=True)
class EvaluationResult:
    """The energy of one swing trajectory on every leg over a gait cycle.

    Attributes:
        robot: The robot.
        cycle: Per leg and phase: samples, energies; robot totals.
        command: The command line that asked for it (``None`` from Python).
    """

    robot: Robot
    cycle: RobotCycle
    command: tuple[str, ...] | None = None

    @property
    def energy_j(self) -> float:
        """Energy of all legs per cycle [J]."""
        return self.cycle.energy_j

    @property
    def average_power_w(self) -> float:
        """Average total leg power [W]."""
        return self.cycle.average_power_w

    @property
    def cost_of_transport(self) -> float:
        """Dimensionless cost of transport."""
        return self.cycle.cost_of_transport

    def to_dict(self) -> dict[str, Any]:
        """Plain data: ``summary.json``."""
        return {"provenance": provenance(self.robot, self.command), **cycle_summary(self.cycle)}

    def write(self, out_dir: str | Path) -> list[Path]:
        """Write ``summary.json`` and ``samples.csv`` into ``out_dir`` (atomically)."""
        out = Path(out_dir)
        return [
            write_atomic(out / "summary.json", to_json(self.to_dict())),
            write_atomic(out / "samples.csv", samples_csv_text(self.cycle)),
        ]


@dataclass(frozen=True)
class OptimizationResult:
    """Optimized swings of some legs, and the cycle they give the robot.

    Attributes:
        robot: The robot.
        reference: The cycle with the reference swing on every leg.
        optima: The optimizer's answer per optimized leg.
        cycle: The cycle with the optimized swings (twins by symmetry, others the reference);
            ``None`` when an optimizer did not converge.
        command: The command line that asked for it (``None`` from Python).
    """

    robot: Robot
    reference: RobotCycle
    optima: dict[str, SwingOptimum]
    cycle: RobotCycle | None
    command: tuple[str, ...] | None = None

    @property
    def success(self) -> bool:
        """Every leg's optimizer converged to a feasible point."""
        return all(o.success for o in self.optima.values())

    def to_dict(self) -> dict[str, Any]:
        """Plain data: ``summary.json`` (the optimized cycle when solved, and every optimum)."""
        data: dict[str, Any] = {"provenance": provenance(self.robot, self.command)}
        if self.cycle is not None:
            data.update(cycle_summary(self.cycle))
        data["solved"] = self.success
        data["optimization"] = {leg: o.as_dict() for leg, o in self.optima.items()}
        data["reference_total_energy_per_cycle_j"] = self.reference.energy_j
        return data

    def write(self, out_dir: str | Path) -> list[Path]:
        """Write ``summary.json`` and ``samples.csv`` (the optimized cycle) into ``out_dir``.

        Raises:
            ConfigError: The optimization did not converge: there is no optimum to write.
        """
        if self.cycle is None:
            raise ConfigError("not solved: there is no optimized cycle to write")
        out = Path(out_dir)
        return [
            write_atomic(out / "summary.json", to_json(self.to_dict())),
            write_atomic(out / "samples.csv", samples_csv_text(self.cycle)),
        ]


def evaluate(
    robot: Robot,
    gait: Gait | None = None,
    *,
    accounting: Accounting = "paper",
    command: Sequence[str] | None = None,
) -> EvaluationResult:
    """Energy of the cubic-spline reference swing on every leg (the paper's Table 6 layout).

    Args:
        robot: The robot (:func:`load_robot`).
        gait: The gait (default: the robot's default trot).
        accounting: ``paper`` (``|tau qd|`` + drive losses), ``positive`` or ``regenerative``.
        command: The command line, recorded in the result's provenance.
    """
    pipeline = EnergyPipeline(robot, gait or read_gait(robot=robot), accounting)
    cycle = pipeline.robot_cycle(make_family("reference"))
    return EvaluationResult(robot, cycle, tuple(command) if command is not None else None)


def optimize_swing(
    robot: Robot,
    gait: Gait | None = None,
    *,
    family: str = DEFAULT_FAMILY,
    method: Method = "ipopt",
    legs: Sequence[str] = FIRST_PAIR,
    accounting: Accounting = "paper",
    precision: float | None = None,
    verbose: bool = False,
    progress: Progress | None = None,
    command: Sequence[str] | None = None,
) -> OptimizationResult:
    """Optimize the swing of ``legs`` (LF and RH repeat RF and LH: the paper's symmetry).

    Args:
        robot: The robot.
        gait: The gait (default: the robot's default trot).
        family: ``paper``, ``joint-N`` or ``fourier-N`` (N in 2..12).
        method: ``ipopt`` or ``pattern`` (the paper's pattern search).
        legs: Legs to optimize; a leg not given takes its twin's optimum, else the reference.
        accounting: Power accounting.
        precision: Pattern-search precision (default 0.1, the paper's); only for ``pattern``.
        verbose: Print Ipopt's own log.
        progress: Called with the leg's name before each leg.
        command: The command line, recorded in the result's provenance.

    Raises:
        ConfigError: A family without parameters, a precision with Ipopt or not > 0.
    """
    check_choice(method, Method, "method")
    swing_family = make_family(family)
    if swing_family.n_params == 0:
        raise ConfigError(f"family {family!r} has no free parameter to optimize", field="family")
    if precision is not None and method != "pattern":
        raise ConfigError(
            "the precision applies to the pattern search only (method 'pattern')",
            field="precision",
        )
    if precision is not None and not precision > 0:
        raise ConfigError(f"the precision must be > 0, got {precision}", field="precision")
    pipeline = EnergyPipeline(robot, gait or read_gait(robot=robot), accounting)
    reference = pipeline.robot_cycle(make_family("reference"))
    options = PatternSearchOptions(precision=precision) if precision is not None else None
    ipopt = VERBOSE_IPOPT if verbose else None
    optima: dict[str, SwingOptimum] = {}
    for leg in legs:
        if progress is not None:
            progress(f"{leg}: {family} by {method}")
        problem = SwingProblem(pipeline, leg, swing_family)
        optima[leg] = run_optimizer(problem, method, pattern_options=options, ipopt_options=ipopt)
    cycle = None
    if all(o.success for o in optima.values()):
        cycle = pipeline.robot_cycle(swing_family, {leg: o.theta for leg, o in optima.items()})
    cmd = tuple(command) if command is not None else None
    return OptimizationResult(robot, reference, optima, cycle, cmd)


@dataclass(frozen=True)
class PaperResult:
    """The paper's Tables 5 and 6 reproduced on a robot (see :mod:`scalf_opt.studies.paper`)."""

    robot: Robot
    reproduction: Reproduction
    command: tuple[str, ...] | None = field(default=None)

    def to_dict(self) -> dict[str, Any]:
        """Plain data: ``paper.json``."""
        return summary(self.reproduction, self.robot, self.command)


def paper(
    robot: Robot | None = None,
    gait: Gait | None = None,
    *,
    verbose: bool = False,
    progress: Progress | None = None,
    command: Sequence[str] | None = None,
) -> PaperResult:
    """Reproduce the paper's Tables 5 and 6 (reference, pattern search, Ipopt) on ``robot``."""
    robot = robot or load_robot("scalf")
    pipeline = EnergyPipeline(robot, gait or read_gait(robot=robot))
    rep = reproduce(pipeline, ipopt_options=VERBOSE_IPOPT if verbose else None, progress=progress)
    return PaperResult(robot, rep, tuple(command) if command is not None else None)


@dataclass(frozen=True)
class SimulationResult:
    """A MuJoCo simulation of the planned trot (extra ``sim``), beside the model's prediction.

    Attributes:
        robot: The robot.
        data: ``simulation.json``: provenance, settings and every figure
            (:mod:`scalf_opt.sim.metrics`), with ``reference`` and ``saving_vs_reference`` when
            the swings are not the reference.
        record: The step-by-step record (:class:`scalf_opt.sim.run.SimRecord`).
        title: A one-line description, for reports and the figure.
    """

    robot: Robot
    data: dict[str, Any]
    record: Any
    title: str

    def to_dict(self) -> dict[str, Any]:
        """Plain data: ``simulation.json``."""
        return self.data

    def write(self, out_dir: str | Path) -> list[Path]:
        """Write ``simulation.json`` and ``simulation.png`` into ``out_dir`` (atomically)."""
        from scalf_opt.viz.figures import save_atomic
        from scalf_opt.viz.simulation_figure import simulation_figure

        out, record = Path(out_dir), self.record
        figure = simulation_figure(
            record.t_s,
            record.trunk[1],
            record.start_trunk_height_m,
            record.trunk[2],
            {leg: force[1] for leg, force in record.grf_n.items()},
            float(self.data["model_stance_force_mean_n"]["RF"]),
            self.title,
        )
        return [
            write_atomic(out / "simulation.json", to_json(self.data)),
            save_atomic(figure, out / "simulation.png"),
        ]

    def write_log(self, path: str | Path, seed: int = 0) -> Path:
        """Write the cylinder log SCalf's sensors would record of the run (80 Hz, 0.1 mm, 70 N).

        Raises:
            LogError: A leg has no hydraulic cylinders.
        """
        from scalf_opt.logs.analysis import leg_cylinders
        from scalf_opt.logs.log_file import log_csv_text
        from scalf_opt.logs.sensors import JointMotion, SensorModel, sensor_log

        pipeline = EnergyPipeline(self.robot, read_gait(robot=self.robot))
        cylinders = {leg: leg_cylinders(pipeline, leg) for leg in self.record.q_rad}
        record = self.record
        motions = {
            leg: JointMotion(
                record.t_s, record.q_rad[leg], record.tau_nm[leg], record.in_contact(leg)
            )
            for leg in cylinders
        }
        log = sensor_log(motions, cylinders, SensorModel(), seed, str(path))
        return write_atomic(path, log_csv_text(log))


def simulate(
    robot: Robot,
    gait: Gait | None = None,
    *,
    swings_from: str | Path | None = None,
    cycles: int = 10,
    accounting: Accounting = "paper",
    servo_bandwidth_hz: float | None = None,
    command: Sequence[str] | None = None,
) -> SimulationResult:
    """Simulate the planned trot in MuJoCo (needs the ``sim`` extra).

    Args:
        robot: The robot.
        gait: The gait (default: the robot's default trot); not with ``swings_from``.
        swings_from: A folder with the ``summary.json`` of ``optimize_swing(...).write(...)``:
            its swings and gait are simulated, and the reference beside them.
        cycles: Gait cycles to simulate (>= 2; the first is the start-up).
        accounting: Power accounting of the joint energies.
        servo_bandwidth_hz: Natural frequency of the joints' PD loops (default 30 Hz).
        command: The command line, recorded in the result's provenance.

    Raises:
        ConfigError: Fewer than 2 cycles, a gait given with ``swings_from``, a bad
            ``summary.json`` or one of another robot, a servo too fast for the time step.
    """
    from scalf_opt.io.saved import read_saved_swings
    from scalf_opt.sim.experiment import simulation_file
    from scalf_opt.sim.plan import REFERENCE_SWINGS
    from scalf_opt.sim.settings import SimSettings

    if isinstance(cycles, bool) or not isinstance(cycles, int) or not 2 <= cycles <= MAX_SIM_CYCLES:
        raise ConfigError(
            f"cycles must be an integer in 2..{MAX_SIM_CYCLES} (the first is the start-up), got "
            f"{cycles!r}",
            field="cycles",
        )
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
    else:
        gait, swings = gait or read_gait(robot=robot), dict(REFERENCE_SWINGS)
    pipeline = EnergyPipeline(robot, gait, accounting)
    source = str(swings_from) if swings_from is not None else None
    data, run = simulation_file(robot, pipeline, swings, settings, cycles, source)
    data = {"provenance": provenance(robot, command), **data}
    families = ", ".join(sorted({family for family, _ in swings.values()}))
    title = (
        f"MuJoCo {data['mujoco_version']} simulation of {robot.name}, {families} swing: trot "
        f"T={gait.period_s:g} s, S={gait.step_length_m:g} m, z0={gait.stance_height_m:g} m, "
        f"{cycles} cycles, dt={1e3 * settings.timestep_s:g} ms, servo "
        f"{settings.servo_bandwidth_hz:g} Hz"
    )
    return SimulationResult(robot, data, run.record, title)


@dataclass(frozen=True)
class LogResult:
    """The energy in a cylinder log (:class:`scalf_opt.logs.analysis.LogAnalysis`).

    Attributes:
        robot: The robot whose cylinders the log comes from.
        analysis: Per leg and phase, the energies over complete cycles.
        command: The command line that asked for it (``None`` from Python).
    """

    robot: Robot
    analysis: Any
    command: tuple[str, ...] | None = None

    @property
    def average_power_w(self) -> float:
        """The robot's mechanical average power [W]."""
        return float(self.analysis.average_power_w)

    def to_dict(self) -> dict[str, Any]:
        """Plain data: what ``analyze-log --json`` prints."""
        return {"provenance": provenance(self.robot, self.command), **self.analysis.as_dict()}


def analyze_log(
    path: str | Path,
    robot: Robot | None = None,
    gait: Gait | None = None,
    *,
    period_s: float | None = None,
    command: Sequence[str] | None = None,
) -> LogResult:
    """The mechanical energy per leg and phase in a cylinder log (the paper's Table 7).

    Args:
        path: The log (CSV: ``t_s,leg,hip_length_m,knee_length_m,hip_force_n,knee_force_n``
            and an optional ``contact``).
        robot: The robot (default: SCalf), for its cylinders and joint limits.
        gait: Its duty cycle and period, where the log does not say (default: the robot's).
        period_s: The gait period [s], over the log's contacts and the gait.
        command: The command line, recorded in the result's provenance.

    Raises:
        LogError: A bad log (the message names the row and the column), or a robot without
            cylinders.
        ConfigError: A period that is not > 0.
    """
    from scalf_opt.logs.analysis import analyze_log as analyze
    from scalf_opt.logs.log_file import read_log

    if period_s is not None and not period_s > 0:
        raise ConfigError(f"the period must be > 0, got {period_s}", field="period_s")
    robot = robot or load_robot("scalf")
    pipeline = EnergyPipeline(robot, gait or read_gait(robot=robot))
    analysis = analyze(read_log(path), pipeline, period_s)
    return LogResult(robot, analysis, tuple(command) if command is not None else None)
