"""``optimize_swing``: the one entry to an optimum, by a family, the bound, or a free stance.

Every consumer gets its optimum here or from the driver under it
(:func:`~scalf_opt.optimize.driver.optimize_swings`): ``scalf-opt optimize``, ``paper``,
studies, ``view``, ``figures`` and the benchmarks. So every optimum is converged in the
sampling, checked against every limit at ten times its rate, retried with Ipopt's other
strategies and started from the same deterministic starts, whoever asked for it.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from scalf_opt.api.gaits import VERBOSE_IPOPT, as_robot, command_tuple, read_gait
from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.energy.limits import leg_bounds, violations
from scalf_opt.energy.loads import DEFAULT_LOADS
from scalf_opt.energy.margins import (
    DEFAULT_EFFORT_SHARE,
    DEFAULT_STOP_MARGIN_RAD,
    DEFAULT_STROKE_MARGIN_M,
    LiftProfile,
    LimitMargins,
)
from scalf_opt.energy.peaks import CycleViolation, Peak, cycle_peaks, cycle_violations
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import ConfigError
from scalf_opt.files import write_atomic
from scalf_opt.io.optimization_records import (
    bound_records,
    leg_record,
    leg_records,
    run_record,
    stance_record,
)
from scalf_opt.io.provenance import provenance
from scalf_opt.io.results import (
    checked_summary,
    samples_csv_text,
    write_results_json,
)
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.family import SwingFamily
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY, FREE_FAMILY, parse_bspline_name
from scalf_opt.locomotion.swing.registry import make_family, optimizable_family
from scalf_opt.model.robot import Robot
from scalf_opt.optimize.bound import FreeBound, bound_cycle_inputs, bounds_for
from scalf_opt.optimize.driver import Settings, SwingOptimization, check_bounded, optimize_swings
from scalf_opt.optimize.free_stance import FreeStance, optimize_stance
from scalf_opt.optimize.goals import BoundGoal, FamilyGoal, Goal, StanceGoal
from scalf_opt.optimize.pattern_search import PatternSearchOptions
from scalf_opt.optimize.solvers import DEFAULT_SOLVER, PatternSearchSolver, solver
from scalf_opt.types import FIRST_PAIR, Accounting, Method, leg_tuple

Progress = Callable[[str], None]
"""Called with a short label as each step of a long computation starts."""


@dataclass(frozen=True)
class OptimizationResult:
    """Optimized swings of some legs, and the cycle they give the robot.

    Attributes:
        robot: The robot.
        pipeline: Robot, gait (at the rate the result converged at) and accounting.
        reference: The cycle with the reference swing on every leg, at the same rate.
        cycle: The cycle with the optimized swings (twins by symmetry, others the reference);
            ``None`` when the optimization did not converge.
        records: ``summary.json``'s optimization records (``optimization``, and as the mode
            has them ``optimization_run``, ``free_bound``, ``free_stance``).
        run: The family optimization (``None`` for the free-trajectory bound).
        bounds: The free-trajectory bound per leg (``family="free"`` or ``bound=True``).
        stance: The stance search (``free_stance=True``).
        command: The command line that asked for it (``None`` from Python).
        settings: How the swings were optimized.
    """

    robot: Robot
    pipeline: EnergyPipeline
    reference: RobotCycle
    cycle: RobotCycle | None
    records: dict[str, Any]
    run: SwingOptimization | None = None
    bounds: dict[str, FreeBound] = field(default_factory=dict)
    stance: FreeStance | None = None
    command: tuple[str, ...] | None = None
    settings: Settings = field(default_factory=Settings)

    @property
    def success(self) -> bool:
        """There is an optimum: every leg solved, energies converged in the sampling."""
        return self.cycle is not None

    @property
    def converged(self) -> bool:
        """Everything asked for converged: the optimum, and the bound or stance search with it."""
        return (
            self.success
            and all(b.success for b in self.bounds.values())
            and (self.stance is None or self.stance.success)
        )

    def failure(self) -> str:
        """What did not converge, in one phrase ('' when everything did)."""
        parts = []
        if self.stance is not None and not self.stance.success:
            parts.append(f"the stance search ({self.stance.best.reason or 'not converged'})")
        if self.run is not None and not self.run.success:
            parts.append(self.run.failure())
        parts += [
            f"the free-trajectory bound of {leg} ({b.status_text()})"
            for leg, b in self.bounds.items()
            if not b.success
        ]
        return ", ".join(parts)

    @property
    def peaks(self) -> list[Peak]:
        """Peak torque, speed, drive outputs and power of the optimized cycle."""
        return cycle_peaks(self._cycle(), self._physics())

    @property
    def reference_peaks(self) -> list[Peak]:
        """The same of the reference cycle."""
        return cycle_peaks(self.reference, self._physics())

    @property
    def violations(self) -> list[CycleViolation]:
        """Every limit a sample of the optimized cycle exceeds (none, for a solved optimum)."""
        return cycle_violations(self._cycle(), self._physics())

    def _cycle(self) -> RobotCycle:
        if self.cycle is None:
            raise ConfigError("not solved: there is no optimized cycle")
        return self.cycle

    def _physics(self) -> dict[str, Any]:
        return {leg: self.pipeline.physics(leg) for leg in self.reference.legs}

    def to_dict(self) -> dict[str, Any]:
        """Plain data: ``summary.json`` (the optimized cycle when solved, and every record)."""
        data: dict[str, Any] = {"provenance": provenance(self.robot, self.command)}
        if self.cycle is not None:
            data.update(checked_summary(self.cycle, self.pipeline))
        data["solved"] = self.success
        data["converged"] = self.converged
        data["status"] = "converged" if self.converged else f"not converged: {self.failure()}"
        data.update(self.records)
        data["reference_total_energy_per_cycle_j"] = self.reference.energy_j
        return data

    def write(self, out_dir: str | Path) -> list[Path]:
        """Write ``summary.json`` and ``samples.csv`` (the optimized cycle) into ``out_dir``.

        Raises:
            ConfigError: The optimization did not converge: there is no optimum to write.
        """
        cycle = self._cycle()
        out = Path(out_dir)
        return [
            *write_results_json(out / "summary.json", self.to_dict()),
            write_atomic(out / "samples.csv", samples_csv_text(cycle)),
        ]


def optimize_swing(
    robot: str | Robot,
    gait: Gait | None = None,
    *,
    family: str = DEFAULT_FAMILY,
    method: Method = DEFAULT_SOLVER,
    legs: str | Sequence[str] = FIRST_PAIR,
    accounting: Accounting = "paper",
    precision: float | None = None,
    starts: int = 1,
    bound: bool = False,
    free_stance: bool = False,
    verbose: bool = False,
    progress: Progress | None = None,
    command: Sequence[str] | None = None,
    loads: str = DEFAULT_LOADS,
    stop_margin_rad: float = DEFAULT_STOP_MARGIN_RAD,
    stroke_margin_m: float = DEFAULT_STROKE_MARGIN_M,
    effort_share: float = DEFAULT_EFFORT_SHARE,
    lift: LiftProfile | None = None,
) -> OptimizationResult:
    """Optimize the swing of ``legs`` (LF and RH repeat RF and LH: the paper's symmetry).

    Every optimum is sampled finely enough that its energy has converged (within 0.5 % of ten
    times the rate), respects every joint and drive limit, and is reported beside the reference.

    Args:
        robot: The robot.
        gait: The gait (default: the robot's default trot).
        family: ``paper``, ``joint-N`` or ``fourier-N`` (N in 2..12), or ``free``: the
            free-trajectory bound (dense B-splines refined until the energy converges).
        method: A solver of :data:`~scalf_opt.optimize.solvers.SOLVERS`: ``ipopt`` or
            ``pattern`` (the paper's pattern search).
        legs: Legs to optimize: names (any case) or one name, ``pair`` for RF and LH; a leg not
            given takes its twin's optimum, else the reference.
        accounting: Power accounting.
        precision: Pattern-search precision (default 0.1, the paper's); only for ``pattern``.
        starts: Deterministic starts per leg (the first is the default start; the best is kept).
        bound: Also compute the free-trajectory bound and each optimum's gap to it.
        free_stance: Optimize the stance height and x-offsets with the swing (``legs`` the
            diagonal pair, a family method).
        verbose: Print Ipopt's own log.
        progress: Called with a label as each step starts.
        command: The command line, recorded in the result's provenance.
        loads: The stance load model: ``whole-body`` (a swing pays for the loads it puts on
            the stance legs), ``whole-body-sagittal`` (the same, shared in the sagittal plane) or
            ``trunk`` (the paper's).
        stop_margin_rad: Every optimized joint angle (and the free stance's) stays this far
            inside its range [rad] (default 2 degrees: what the simulated servo needs).
        stroke_margin_m: Every cylinder length stays this far inside its stroke [m] (2 mm).
        effort_share: Every torque and drive force stays this share under its limit (0.05).
        lift: How the swing foot leaves and meets the ground (default: the lift profile of
            :class:`~scalf_opt.energy.margins.LiftProfile`; ``NO_LIFT_PROFILE``: only above it).

    Raises:
        ConfigError: A margin < 0 or one that leaves no range; a family without parameters, a
            precision with Ipopt or not > 0, an accounting with nothing to optimize, options
            that do not go together.
    """
    goal = goal_from(
        family=family,
        method=method,
        legs=legs,
        precision=precision,
        starts=starts,
        bound=bound,
        free_stance=free_stance,
        verbose=verbose,
        margins=LimitMargins(stop_margin_rad, stroke_margin_m, effort_share, lift or LiftProfile()),
    )
    robot = as_robot(robot)
    pipeline = EnergyPipeline(robot, gait or read_gait(robot=robot), accounting, loads=loads)
    return optimize_goal(robot, pipeline, goal, progress, command)


def goal_from(
    *,
    family: str = DEFAULT_FAMILY,
    method: Method = DEFAULT_SOLVER,
    legs: str | Sequence[str] = FIRST_PAIR,
    precision: float | None = None,
    starts: int = 1,
    bound: bool = False,
    free_stance: bool = False,
    verbose: bool = False,
    margins: LimitMargins | None = None,
) -> Goal:
    """The goal that :func:`optimize_swing`'s names and flags ask for (the arguments are its).

    The one place the names become objects: ``family="free"`` is the :class:`BoundGoal`,
    ``free_stance`` the :class:`StanceGoal`, any other family a :class:`FamilyGoal`.

    Raises:
        ConfigError: Options that do not go together; see :func:`optimize_swing`.
    """
    leg_names = leg_tuple(legs)
    margins = margins or LimitMargins()
    _check_precision(method, precision)
    if family == FREE_FAMILY:
        if bound or free_stance or starts != 1 or method != DEFAULT_SOLVER:
            raise ConfigError(
                "family free is the free-trajectory bound itself (Ipopt on dense B-splines): "
                "no --bound, --free-stance, --starts or --method with it",
                field="family",
            )
        return BoundGoal(leg_names, margins)
    swing_family = _optimizable_family(family)
    settings = Settings(
        method=method,
        starts=starts,
        pattern=PatternSearchOptions(precision=precision or PatternSearchOptions().precision),
        ipopt=VERBOSE_IPOPT if verbose else None,
        margins=margins,
    )
    if free_stance:
        if leg_names != FIRST_PAIR:
            raise ConfigError(
                "the free stance optimizes the diagonal pair's swings: legs RF and LH",
                field="free_stance",
            )
        return StanceGoal(swing_family, settings)
    return FamilyGoal(leg_names, swing_family, settings, with_bound=bound)


def optimize_goal(
    robot: Robot,
    pipeline: EnergyPipeline,
    goal: Goal,
    progress: Progress | None = None,
    command: Sequence[str] | None = None,
) -> OptimizationResult:
    """Reach ``goal`` on ``pipeline`` (the robot's gait, accounting and loads).

    Raises:
        ConfigError: Margins the gait's own stance does not keep (a family's legs).
    """
    cmd = command_tuple(command)
    if isinstance(goal, BoundGoal):
        _check_stance_margins(pipeline, goal.legs, goal.margins)
        return _free_method(robot, pipeline, goal.legs, progress, cmd, goal.margins)
    if isinstance(goal, StanceGoal):  # it searches stances that keep the margins
        if progress is not None:
            progress(f"the stance and the {goal.family.name} swings")
        return _free_stance(robot, pipeline, goal.family, goal.settings, cmd)
    _check_stance_margins(pipeline, goal.legs, goal.settings.margins)
    return _swings(
        robot, pipeline, goal.legs, goal.family, goal.settings, goal.with_bound, progress, cmd
    )


def _check_precision(method: Method, precision: float | None) -> None:
    """A precision is the pattern search's, and > 0."""
    if precision is not None and not isinstance(solver(method), PatternSearchSolver):
        raise ConfigError(
            "the precision applies to the pattern search only (method 'pattern')",
            field="precision",
        )
    if precision is not None and not precision > 0:
        raise ConfigError(f"the precision must be > 0, got {precision}", field="precision")


def _optimizable_family(family: str) -> SwingFamily:
    """The family ``family`` names, when it has parameters to optimize (not B-splines)."""
    if parse_bspline_name(family) is not None:
        raise ConfigError(
            f"family {family}: B-splines are the free-trajectory bound's: family 'free'",
            field="family",
        )
    return optimizable_family(family)


def _free_stance(
    robot: Robot,
    pipeline: EnergyPipeline,
    family: SwingFamily,
    settings: Settings,
    cmd: tuple[str, ...] | None,
) -> OptimizationResult:
    """The stance height and x-offsets optimized with the diagonal pair's swings."""
    stance = optimize_stance(pipeline, family, settings)
    run = stance.best.run
    records: dict[str, Any] = {
        "limit_margins": settings.margins.for_family(family.n_params).to_dict(pipeline.gait),
        "free_stance": stance_record(stance),
    }
    solved = run is not None and run.success
    if run is not None and run.success:
        records.update(
            optimization=leg_records(run),
            optimization_run=run_record(run),
        )
    return OptimizationResult(
        robot,
        run.pipeline if run is not None and solved else pipeline,
        stance.reference,
        stance.cycle() if solved else None,
        records,
        run,
        stance=stance,
        command=cmd,
        settings=settings,
    )


def _swings(
    robot: Robot,
    pipeline: EnergyPipeline,
    legs: tuple[str, ...],
    family: SwingFamily,
    settings: Settings,
    bound: bool,
    progress: Progress | None,
    cmd: tuple[str, ...] | None,
) -> OptimizationResult:
    """The legs' swings optimized on the pipeline's gait; with ``bound``, the bound beside."""
    run = optimize_swings(pipeline, legs, family, settings, progress=progress)
    records: dict[str, Any] = {
        "limit_margins": settings.margins.for_family(family.n_params).to_dict(pipeline.gait),
        "optimization": leg_records(run),
        "optimization_run": run_record(run),
    }
    bounds: dict[str, FreeBound] = {}
    if bound and run.success:
        seeds = {leg: [(family, r.best.theta)] for leg, r in run.legs.items()}
        bounds = bounds_for(
            pipeline, tuple(run.legs), seeds, progress=progress, margins=settings.margins
        )
        run = run.with_bound_checks({leg: b.check_energy_j for leg, b in bounds.items()})
        records["optimization"] = leg_records(run)
        records["free_bound"] = bound_records(bounds)
    return OptimizationResult(
        robot,
        run.pipeline,
        run.reference_cycle(),
        run.cycle() if run.success else None,
        records,
        run,
        bounds,
        command=cmd,
        settings=settings,
    )


def _check_stance_margins(
    pipeline: EnergyPipeline, legs: tuple[str, ...], margins: LimitMargins
) -> None:
    """Refuse margins the gait's own stance does not keep: no swing could then keep them.

    Raises:
        ConfigError: A stance sample lies inside a margin (the message names the leg, the
            quantity and the option).
    """
    for leg in legs:
        phase = pipeline.stance(leg)
        # only the range and the stroke: a stance beyond a rate, torque or force limit (or its
        # effort margin) is the gait's (reported with the peaks), and under whole-body loads it
        # depends on the swings, whose optimizer keeps the loaded stance in its effort margin
        beyond = [
            v
            for v in violations(phase.values, margins.apply(leg_bounds(pipeline.physics(leg))))
            if margins.margin(v.bound) > 0 and margins.field_of(v.bound) != "effort_share"
        ]
        if beyond:
            bound = beyond[0].bound
            field = "stop_margin_rad" if bound.output == "q" else "stroke_margin_m"
            raise ConfigError(
                f"the stance of {leg} at this gait takes {bound.name} within "
                f"{margins.margin(bound):g} {bound.unit} of the end of its "
                f"{bound.source.removesuffix(', less margin')}: no swing can keep that margin "
                f"({field}); give a smaller one or another stance",
                field=field,
            )


def _free_method(
    robot: Robot,
    pipeline: EnergyPipeline,
    legs: tuple[str, ...],
    progress: Progress | None,
    command: tuple[str, ...] | None,
    margins: LimitMargins,
) -> OptimizationResult:
    """The free-trajectory bound of each leg, reported as an optimum."""
    check_bounded(pipeline, legs)
    bounds = bounds_for(pipeline, legs, progress=progress, margins=margins)
    records: dict[str, Any] = {
        "limit_margins": margins.to_dict(pipeline.gait),
        "free_bound": bound_records(bounds),
    }
    if not all(b.result.success for b in bounds.values()):  # not even a level solved
        reference = pipeline.robot_cycle(make_family("reference"))
        return OptimizationResult(
            robot, pipeline, reference, None, records, bounds=bounds, command=command
        )
    at_rate, family, thetas = bound_cycle_inputs(pipeline, bounds)
    records["optimization"] = {
        leg: {
            **leg_record(b.result),
            "family": family.name,
            "method": DEFAULT_SOLVER,
            "parameters": dict(zip(family.parameter_names, map(float, thetas[leg]), strict=True)),
        }
        for leg, b in bounds.items()
    }
    return OptimizationResult(
        robot,
        at_rate,
        at_rate.robot_cycle(make_family("reference")),
        at_rate.robot_cycle(family, thetas),
        records,
        bounds=bounds,
        command=command,
    )
