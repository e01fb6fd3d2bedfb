"""Optimize the swing of several legs: the one code path of ``optimize`` and ``paper``.

:func:`optimize_swings` runs an optimizer (pattern search or Ipopt) on each leg with the same
start and options whoever calls it, refines the sampling until the optimum's energy has
converged (:mod:`scalf_opt.optimize.sampling`), runs the extra starts asked for
(:mod:`scalf_opt.optimize.starts`), and sets every optimum beside the reference swing at the same
rate. A failed start is reported, not fatal; a leg is solved when its best start converged to
a feasible point whose energy has converged in the sampling. With Ipopt the legs are solved on
parallel threads, as many as the process may use (:func:`~scalf_opt.workers.thread_budget`:
its cores, one in a worker process beside others); their answers do not depend on it, and their
time hardly either (Ipopt's MUMPS factorizes one system at a time per process).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field, replace
from functools import cached_property, partial
from typing import Any

import casadi as ca
import numpy as np

from scalf_opt.energy.accounting import accounting as power_accounting
from scalf_opt.energy.cycle import RobotCycle
from scalf_opt.energy.margins import DEFAULT_MARGINS, LimitMargins
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.errors import ConfigError, GaitError, InfeasibleError
from scalf_opt.interrupts import map_in_threads, raise_if_stopped
from scalf_opt.locomotion.swing.family import SwingFamily
from scalf_opt.locomotion.swing.registry import check_optimizable, make_family
from scalf_opt.locomotion.trot import DIAGONAL_PARTNER
from scalf_opt.optimize.pattern_search import PatternSearchOptions
from scalf_opt.optimize.problem import PairProblem, SwingGoal
from scalf_opt.optimize.sampling import (
    BETWEEN_SAMPLES_RTOL,
    SAMPLING_TOLERANCE,
    Transcription,
    on_check_grid,
    relative_difference,
)
from scalf_opt.optimize.solve import SwingOptimum
from scalf_opt.optimize.solvers import (
    DEFAULT_SOLVER,
    FIRST_ROUND_ITERATIONS,
    SolverOptions,
    solver,
)
from scalf_opt.optimize.starts import starts
from scalf_opt.types import Method
from scalf_opt.workers import thread_budget


@dataclass(frozen=True)
class Settings:
    """How to optimize (the defaults of ``scalf-opt optimize`` and ``scalf-opt paper``).

    Attributes:
        method: The solver's name (:data:`~scalf_opt.optimize.solvers.SOLVERS`).
        starts: Number of deterministic starts per leg (the first is the default start).
        pattern: Pattern-search settings (the paper's by default).
        sampling_tolerance: Largest relative difference between the optimum's energy at its
            rate and at ten times that rate.
        ipopt: Extra Ipopt options (``{"print_level": 5}``: its iteration log), or ``None``.
        margins: How far inside the joint range and the cylinder stroke every optimum stays.
        screen: Ipopt leaves out the rows far from their bounds at its start
            (:mod:`scalf_opt.optimize.screening`): for starts at a neighbouring optimum.
        pair_together: Under loads that couple the legs, a diagonal pair is one problem for a
            solver that takes it (Ipopt); ``False``: its legs are optimized in turn, as the
            pattern search does (what ``benchmarks/bench_pair.py`` compares).
    """

    method: Method = DEFAULT_SOLVER
    starts: int = 1
    pattern: PatternSearchOptions = field(default_factory=PatternSearchOptions)
    sampling_tolerance: float = SAMPLING_TOLERANCE
    ipopt: dict[str, Any] | None = None
    margins: LimitMargins = DEFAULT_MARGINS
    screen: bool = False
    pair_together: bool = True

    def __post_init__(self) -> None:
        solver(self.method)  # a name no solver has: ConfigError
        if isinstance(self.starts, bool) or not isinstance(self.starts, int) or self.starts < 1:
            raise ConfigError(
                f"the number of starts must be an integer >= 1, got {self.starts!r}", field="starts"
            )

    @property
    def solver_options(self) -> SolverOptions:
        """The options the solvers read."""
        return SolverOptions(self.pattern, self.ipopt, self.screen)


@dataclass(frozen=True)
class Check:
    """An optimum's energies on the check grid, ten times its rate [J].

    ``inf`` when the optimum failed, or crosses a bound between the samples by more than
    :data:`~scalf_opt.optimize.sampling.BETWEEN_SAMPLES_RTOL` of the bound.

    Attributes:
        objective_j: The objective (the swing energy, plus under whole-body loads the stance
            energy the swing loads).
        swing_j: The leg's own swing energy.
    """

    objective_j: float
    swing_j: float

    def error(self, optimum: SwingOptimum) -> float:
        """How far what a report prints of ``optimum`` is from this check, relatively.

        The largest relative difference of its objective, its swing energy and the stance part
        the objective adds (under trunk loads the objective is the swing energy): an optimum
        has converged in the sampling when every energy printed of it has, not their sum alone
        (a ``joint-12`` swing 1.1 % off its converged energy hid in a whole-body objective
        0.17 % off).
        """
        if not (math.isfinite(self.objective_j) and math.isfinite(optimum.objective_j)):
            return math.inf
        stance = optimum.objective_j - optimum.swing_energy_j
        check_stance = self.objective_j - self.swing_j
        return max(
            relative_difference(optimum.objective_j, self.objective_j),
            relative_difference(optimum.swing_energy_j, self.swing_j),
            0.0 if stance == check_stance == 0.0 else relative_difference(stance, check_stance),
        )


FAILED_CHECK = Check(math.inf, math.inf)
"""The check of an optimum that failed or crossed a bound between samples."""


@dataclass(frozen=True)
class StartResult:
    """One start of one leg.

    Attributes:
        label: Where it started (``zero``, ``closest to the reference``, ...).
        optimum: The optimizer's answer at the final rate.
        check_energy_j: Its objective (the swing energy; under whole-body loads plus the
            pair's stance energy) at ten times the rate [J] (inf if it failed).
        converged: Solved, and its energies converged in the sampling (:meth:`Check.error`).
        check_swing_energy_j: Its swing energy alone at ten times the rate [J].
    """

    label: str
    optimum: SwingOptimum
    check_energy_j: float
    converged: bool
    check_swing_energy_j: float = math.nan

    @classmethod
    def checked(
        cls, label: str, optimum: SwingOptimum, check: Check, tolerance: float
    ) -> StartResult:
        """The start's answer with its check.

        Converged when solved and every printed energy agrees with its check within
        ``tolerance`` (:meth:`Check.error`).
        """
        converged = optimum.success and check.error(optimum) <= tolerance
        return cls(label, optimum, check.objective_j, converged, check.swing_j)


@dataclass(frozen=True)
class LegResult:
    """The optimization of one leg.

    Attributes:
        leg: Leg name.
        best: The best converged start (else the first start).
        starts: Every start, in order.
        reference_swing_energy_j: The reference swing's energy at the same rate [J] (NaN when
            the reference leaves the joint range at this gait).
        check_energy_j: The best optimum's objective at ten times the rate [J] (see
            :class:`StartResult`).
        sampling_error: Relative difference of the two energies.
        check_swing_energy_j: The best optimum's swing energy alone at ten times the rate [J]
            (``check_energy_j`` unless the objective adds the stance: whole-body loads).
        sampling_error: The largest relative difference of the best optimum's printed energies
            (objective, swing, stance part) from their checks (:meth:`Check.error`).
        bound_check_energy_j: The free-trajectory bound at ten times its rate, when computed
            [J] (:mod:`scalf_opt.optimize.bound`).
    """

    leg: str
    best: SwingOptimum
    starts: list[StartResult]
    reference_swing_energy_j: float
    check_energy_j: float
    sampling_error: float
    bound_check_energy_j: float | None = None
    check_swing_energy_j: float | None = None

    @property
    def success(self) -> bool:
        """The best start is solved and its energy converged in the sampling."""
        return any(s.converged for s in self.starts)

    @property
    def worse_than_reference(self) -> bool:
        """The optimum costs more than the reference swing."""
        return self.best.swing_energy_j > self.reference_swing_energy_j

    @property
    def change_percent(self) -> float:
        """Swing energy change against the reference [%]."""
        return 100.0 * (self.best.swing_energy_j / self.reference_swing_energy_j - 1.0)

    @property
    def gap_to_bound_percent(self) -> float | None:
        """How far above the free-trajectory bound the optimum is [%], when it is known.

        Both swing energies at ten times their optimization rates: the converged energies
        (the bound is on the swing energy alone, under any stance loads).
        """
        if self.bound_check_energy_j is None:
            return None
        swing = (
            self.check_energy_j if self.check_swing_energy_j is None else self.check_swing_energy_j
        )
        return 100.0 * (swing / self.bound_check_energy_j - 1.0)

    @property
    def spread_j(self) -> float:
        """Largest minus smallest swing energy of the converged starts [J] (0 for one)."""
        energies = [s.optimum.objective_j for s in self.starts if s.converged]
        return max(energies) - min(energies) if energies else math.nan


@dataclass(frozen=True)
class SwingOptimization:
    """The optimization of several legs with one family and method.

    Attributes:
        family: The family.
        settings: How it was optimized.
        pipeline: The pipeline at the rate the optimization converged at.
        legs: Result per leg.
        rates_hz: Every rate tried, the last one the rate of the results.
        converged_sampling: The energies converged within the tolerance.
        wall_time_s: Time of the whole optimization [s].
        rounds: Rounds of the coupled legs' alternation at the final rate (1 when the legs are
            independent: trunk-only loads, or one leg; or solved together).
        alternation_settled: The last round changed the coupled legs' energy by less than
            :data:`ALTERNATION_RTOL` (always true for independent legs); else the alternation
            stopped at :data:`MAX_ALTERNATIONS` rounds and the pair is not converged.
        solved_together: The coupled legs were optimized as one problem (one NLP over both
            legs' swings, :class:`~scalf_opt.optimize.problem.PairProblem`), not in turn.
    """

    family: SwingFamily
    settings: Settings
    pipeline: EnergyPipeline
    legs: dict[str, LegResult]
    rates_hz: list[float]
    converged_sampling: bool
    wall_time_s: float = 0.0
    rounds: int = 1
    alternation_settled: bool = True
    solved_together: bool = False

    @property
    def coupled(self) -> bool:
        """The legs' problems are coupled (whole-body loads, several legs)."""
        return legs_coupled(self.pipeline, tuple(self.legs))

    @property
    def rate_hz(self) -> float:
        """The rate of the results [Hz]."""
        return self.rates_hz[-1]

    @property
    def success(self) -> bool:
        """Every leg solved, with converged energies (and a settled alternation)."""
        return (
            self.converged_sampling
            and self.alternation_settled
            and all(r.success for r in self.legs.values())
        )

    @property
    def rounds_text(self) -> str:
        """``1 round``, ``3 rounds``: the alternation's rounds in words."""
        return f"{self.rounds} round{'' if self.rounds == 1 else 's'}"

    def failure(self) -> str:
        """What did not converge, in one phrase ('' when everything did)."""
        parts = [f"{r.leg} ({r.best.status})" for r in self.legs.values() if not r.success]
        if not self.converged_sampling and not parts:
            parts.append(f"the sampling by {self.rate_hz:g} Hz")
        if not self.alternation_settled and not parts:
            parts.append(f"the legs' alternation (stopped after {self.rounds_text})")
        return ", ".join(parts)

    @property
    def thetas(self) -> dict[str, np.ndarray]:
        """The best parameters per leg."""
        return {leg: r.best.theta for leg, r in self.legs.items()}

    def cycle(self) -> RobotCycle:
        """The robot's cycle with the optima (legs not optimized: their twin's, or reference).

        Evaluated once (the result is frozen); every report reads the same cycle.
        """
        return self._optimized_cycle

    def reference_cycle(self) -> RobotCycle:
        """The robot's cycle with the reference swing, at the same rate (evaluated once)."""
        return self._reference_cycle

    @cached_property
    def _optimized_cycle(self) -> RobotCycle:
        return self.pipeline.robot_cycle(self.family, self.thetas)

    @cached_property
    def _reference_cycle(self) -> RobotCycle:
        return self.pipeline.robot_cycle(make_family("reference"))

    def with_bound_checks(self, check_energy_j: Mapping[str, float]) -> SwingOptimization:
        """The same optimization with the legs' free-trajectory bounds beside them.

        ``check_energy_j``: each bounded leg's bound energy at ten times its rate [J], which the
        leg's gap to the bound is reported against.
        """
        legs = {
            leg: replace(r, bound_check_energy_j=check_energy_j[leg])
            if leg in check_energy_j
            else r
            for leg, r in self.legs.items()
        }
        return replace(self, legs=legs)


def check_bounded(pipeline: EnergyPipeline, legs: tuple[str, ...]) -> None:
    """Refuse an accounting under which the swing energy has nothing to minimize.

    Under ``regenerative`` the charged joint power integrates to the change of the leg's
    mechanical energy, the same for every swing between the same end states (the work-energy
    theorem; the leg frame is inertial). A leg whose drives lose nothing then has a constant
    swing energy: any swing is optimal, and an optimizer only exploits the sampling. With
    losses (SCalf's friction heat) the energy is that constant plus the losses: bounded below,
    and the limits and the sampling refinement keep the optimizer honest.

    Raises:
        ConfigError: The accounting is ``regenerative`` and a leg's drives have no losses.
    """
    if power_accounting(pipeline.accounting).optimizable_without_losses():
        return
    q, qd, tau = (ca.SX.sym(n) for n in ("q", "qd", "tau"))
    for leg in legs:
        drives = pipeline.physics(leg).drives
        if all(ca.SX(d.loss_rate(q, qd, tau)).is_zero() for d in drives):
            raise ConfigError(
                f"--accounting {pipeline.accounting}: the drives of leg {leg} lose nothing, "
                "so every swing between the same end states costs the same energy (the change "
                "of the leg's mechanical energy); there is nothing to optimize"
            )


def reference_swing_energy_j(pipeline: EnergyPipeline, leg: str) -> float:
    """The reference swing's energy [J]; NaN when it leaves the joint range at this gait."""
    try:
        return float(pipeline.swing(leg, make_family("reference")).energy_j.sum())
    except (InfeasibleError, GaitError):  # the reference's own path is the gait's: GaitError
        return math.nan


ALTERNATION_RTOL = 1e-5
"""The coupled legs' alternation stops when a round changes their energy by less than this."""

MAX_ALTERNATIONS = 8
"""Most rounds of the coupled legs' alternation at one rate."""


def _solve_leg(
    pipeline: EnergyPipeline,
    leg: str,
    family: SwingFamily,
    settings: Settings,
    theta0: np.ndarray | None,
    others: Mapping[str, np.ndarray] | None = None,
    trial: bool = False,
) -> tuple[SwingOptimum, Check]:
    """Optimize one leg at the pipeline's rate; also return the energy at ten times the rate.

    That energy is ``inf`` when the optimum crosses a bound between its samples by more than
    :data:`BETWEEN_SAMPLES_RTOL` of the bound (on the same ten times finer samples): the rate
    does not resolve the optimum, exactly as when the energy has not converged. ``trial``: a
    warm solve (:mod:`scalf_opt.optimize.solvers`), one trial of a search.
    """
    raise_if_stopped()
    problem = SwingGoal(family, settings.margins).on(pipeline, leg, others)
    if theta0 is None:
        theta0 = np.zeros(problem.n_params)
    optimum = solver(settings.method).solve(problem, theta0, settings.solver_options, warm=trial)
    return optimum, _check(pipeline, leg, family, settings, optimum, others)


def _check(
    pipeline: EnergyPipeline,
    leg: str,
    family: SwingFamily,
    settings: Settings,
    optimum: SwingOptimum,
    others: Mapping[str, np.ndarray] | None,
) -> Check:
    """The optimum's energies at ten times the rate (:class:`Check`)."""
    if not optimum.success:
        return FAILED_CHECK
    fine_pipeline = on_check_grid(pipeline)
    fine = SwingGoal(family, settings.margins).on(fine_pipeline, leg, others)
    check, crossed = fine.energy_and_bound_excess(optimum.theta)
    if crossed > BETWEEN_SAMPLES_RTOL:
        return FAILED_CHECK
    swing = fine.swing_energy_j(optimum.theta) if fine.couplings else check
    return Check(check, swing)


def _solve_one(
    pipeline: EnergyPipeline,
    family: SwingFamily,
    settings: Settings,
    theta0: Mapping[str, np.ndarray | None],
    trial: bool,
    leg: str,
) -> tuple[SwingOptimum, Check]:
    return _solve_leg(pipeline, leg, family, settings, theta0[leg], trial=trial)


def legs_coupled(pipeline: EnergyPipeline, legs: tuple[str, ...]) -> bool:
    """Whether ``legs``' problems depend on each other: whole-body loads and several legs."""
    return pipeline.load_model.couples_legs and len(legs) > 1


def _solve_legs(
    pipeline: EnergyPipeline,
    legs: tuple[str, ...],
    family: SwingFamily,
    settings: Settings,
    current: Mapping[str, np.ndarray | None],
    workers: int = 1,
    trial: bool = False,
    pair_start: bool = False,
) -> tuple[dict[str, tuple[SwingOptimum, Check]], int, bool, bool]:
    """Optimize every leg at the pipeline's rate.

    Returns the answers, the rounds, whether they settled, and whether the legs were solved
    together. Under trunk loads each leg is its own problem: one round. Under whole-body loads
    a leg's objective depends on the other optimized legs' swings (their twins load the same
    stance feet). A diagonal pair is then one problem (:class:`PairProblem`) for a solver that
    takes it (Ipopt: one NLP over both legs' swings, which reaches the pair's optimum in one
    solve). Otherwise the legs are optimized in turn, each with the others' latest parameters,
    until a round changes their summed objective by less than :data:`ALTERNATION_RTOL` (block
    coordinate descent on the pair's energy: no round makes it worse), at most
    :data:`MAX_ALTERNATIONS` rounds; the alternation has settled when its last round met the
    tolerance (independent legs: always). ``pair_start``: ``current`` is already the pair's
    optimum (at another rate), so the pair's problem starts there, without a first round.
    """
    if not legs_coupled(pipeline, legs):
        # independent problems: on parallel threads when the solver allows it
        solved = map_in_threads(
            partial(_solve_one, pipeline, family, settings, current, trial), legs, workers
        )
        return dict(zip(legs, solved, strict=True)), 1, True, False
    thetas: dict[str, np.ndarray] = {
        leg: np.zeros(family.n_params) if (theta := current[leg]) is None else theta for leg in legs
    }
    if settings.pair_together and one_pair(legs) and solver(settings.method).solves_pairs:
        return (
            _solve_pair(pipeline, legs, family, settings, thetas, trial, pair_start),
            1,
            True,
            True,
        )
    return _alternate(pipeline, legs, family, settings, thetas, trial)


def _solve_pair(
    pipeline: EnergyPipeline,
    legs: tuple[str, ...],
    family: SwingFamily,
    settings: Settings,
    thetas: dict[str, np.ndarray],
    trial: bool,
    pair_start: bool,
) -> dict[str, tuple[SwingOptimum, Check]]:
    """A diagonal pair as one problem, each leg's optimum with its check.

    With ``trial`` or ``pair_start`` (see :func:`_solve_legs`), ``thetas`` is already a
    (neighbouring) pair's optimum; else the pair starts where one round of its legs in turn
    ends (:func:`_first_round`). A trial's solve is warm.
    """
    chosen = solver(settings.method)
    pair = PairProblem(pipeline, legs, family, settings.margins)
    started = trial or pair_start
    start = thetas if started else _first_round(pipeline, legs, family, settings, thetas)
    together = chosen.solve_pair(pair, start, settings.solver_options, warm=trial)
    final = {leg: o.theta for leg, o in together.items()}
    return {
        leg: (
            optimum,
            _check(
                pipeline, leg, family, settings, optimum, coupled_others(pipeline, legs, leg, final)
            ),
        )
        for leg, optimum in together.items()
    }


def _alternate(
    pipeline: EnergyPipeline,
    legs: tuple[str, ...],
    family: SwingFamily,
    settings: Settings,
    thetas: dict[str, np.ndarray],
    trial: bool,
) -> tuple[dict[str, tuple[SwingOptimum, Check]], int, bool, bool]:
    """The coupled legs in turn, each beside the others' latest, until the rounds settle."""
    answers: dict[str, tuple[SwingOptimum, Check]] = {}
    previous = math.inf
    for round_ in range(1, MAX_ALTERNATIONS + 1):
        for leg in legs:
            others = {o: theta for o, theta in thetas.items() if o != leg}
            answers[leg] = _solve_leg(
                pipeline, leg, family, settings, thetas[leg], others, trial=trial
            )
            if answers[leg][0].success:
                thetas[leg] = answers[leg][0].theta
        if not all(o.success for o, _ in answers.values()):
            return answers, round_, True, False  # a failed leg is the run's status
        total = answers[legs[-1]][0].objective_j + sum(
            answers[leg][0].swing_energy_j for leg in legs[:-1]
        )
        if abs(previous - total) <= ALTERNATION_RTOL * abs(total):
            return answers, round_, True, False
        previous = total
    return answers, MAX_ALTERNATIONS, False, False


def _first_round(
    pipeline: EnergyPipeline,
    legs: tuple[str, ...],
    family: SwingFamily,
    settings: Settings,
    start: Mapping[str, np.ndarray],
) -> dict[str, np.ndarray]:
    """The start of a pair's problem: one round of its legs in turn from ``start``.

    The pair's energy has several local minima. Started where one round of the legs in turn
    ends, the pair's problem goes on from the basin the legs in turn would settle in, to the
    pair's stationary point, where the rounds stall short of it. Measured with
    ``benchmarks/bench_pair.py`` on six robots' default pairs: never above the legs in turn,
    0.8 to 0.9 % below them on ANYmal C and HyQ; straight from ``start`` it was 0.8 % above on
    Go1. Its solves only start the pair's: Ipopt's first strategy gets
    :data:`~scalf_opt.optimize.solvers.FIRST_ROUND_ITERATIONS` before the next is tried.
    """
    current = dict(start)
    options = replace(settings.solver_options, first_strategy_iterations=FIRST_ROUND_ITERATIONS)
    for leg in legs:
        others = {o: current[o] for o in legs if o != leg}
        problem = SwingGoal(family, settings.margins).on(pipeline, leg, others)
        answer = solver(settings.method).solve(problem, current[leg], options)
        if answer.success:
            current[leg] = answer.theta
    return current


def one_pair(legs: tuple[str, ...]) -> bool:
    """Whether ``legs`` are one leg and its diagonal partner (a pair solved as one problem)."""
    return len(legs) == 2 and DIAGONAL_PARTNER[legs[0]] == legs[1]


def coupled_others(
    pipeline: EnergyPipeline, legs: tuple[str, ...], leg: str, thetas: Mapping[str, np.ndarray]
) -> dict[str, np.ndarray] | None:
    """The other optimized legs' parameters a leg's problem holds fixed (``None``: uncoupled)."""
    if not pipeline.load_model.couples_legs:
        return None
    return {o: thetas[o] for o in legs if o != leg}


def _first_starts(
    pipeline: EnergyPipeline,
    legs: tuple[str, ...],
    family: SwingFamily,
    settings: Settings,
    theta0: Mapping[str, np.ndarray] | None,
) -> dict[str, tuple[str, np.ndarray]]:
    """Each leg's first start and its label: ``theta0``'s (``given``), else the default."""
    first: dict[str, tuple[str, np.ndarray]] = {}
    for leg in legs:
        if theta0 is not None and leg in theta0:
            first[leg] = ("given", np.asarray(theta0[leg], dtype=float))
        else:
            problem = SwingGoal(family, settings.margins).on(pipeline, leg)
            first[leg] = starts(problem, solver(settings.method), 1)[0]
    return first


def _refined(
    pipeline: EnergyPipeline,
    legs: tuple[str, ...],
    family: SwingFamily,
    settings: Settings,
    current: Mapping[str, np.ndarray | None],
    trial: bool,
    rates: list[float],
    progress: Callable[[str], None] | None,
) -> tuple[EnergyPipeline, dict[str, tuple[SwingOptimum, Check]], tuple[int, bool, bool], bool]:
    """The legs solved at the family's first rate, the rate doubled until they converge.

    Converged: each optimum's objective agrees with its check (module docstring). ``rates``
    gets each rate tried.

    Returns:
        The pipeline at the last rate, each leg's optimum and check there, the alternation's
        (rounds, settled, together), and whether the sampling converged.
    """
    transcription = Transcription.first(pipeline.gait, family)
    workers = thread_budget() if solver(settings.method).releases_gil else 1
    while True:
        rates.append(transcription.rate_hz)
        if progress is not None:
            progress(f"{family.name} at {transcription.rate_hz:g} Hz")
        at_rate = transcription.on(pipeline)
        answers, rounds, settled, together = _solve_legs(
            at_rate, legs, family, settings, dict(current), workers, trial, len(rates) > 1
        )
        alternation = (rounds, settled, together)
        if not all(o.success for o, _ in answers.values()):
            return at_rate, answers, alternation, False
        errors = [c.error(o) for o, c in answers.values()]
        if all(e <= settings.sampling_tolerance for e in errors):  # inf / inf is NaN: not met
            return at_rate, answers, alternation, True
        if transcription.finest:
            return at_rate, answers, alternation, False
        transcription = transcription.refined()
        current = {leg: o.theta for leg, (o, _) in answers.items()}


def _leg_result(
    at_rate: EnergyPipeline,
    legs: tuple[str, ...],
    leg: str,
    family: SwingFamily,
    settings: Settings,
    answer: tuple[SwingOptimum, Check],
    first_label: str,
    final: Mapping[str, np.ndarray],
    trial: bool,
    progress: Callable[[str], None] | None,
) -> LegResult:
    """One leg's result at the converged rate: its first answer, the extra starts', the best."""
    tolerance = settings.sampling_tolerance
    runs = [StartResult.checked(first_label, *answer, tolerance)]
    others = coupled_others(at_rate, legs, leg, final)
    problem = SwingGoal(family, settings.margins).on(at_rate, leg, others)
    extra = 1 if trial else settings.starts  # a trial is one warm solve: no extra start
    for label, theta in starts(problem, solver(settings.method), extra)[1:]:
        if progress is not None:
            progress(f"{leg}: start {label}")
        other = _solve_leg(at_rate, leg, family, settings, theta, others)
        runs.append(StartResult.checked(label, *other, tolerance))
    good = [r for r in runs if r.converged]
    best = min(good, key=lambda r: r.optimum.objective_j) if good else runs[0]
    check_energy, check_swing = best.check_energy_j, best.check_swing_energy_j
    if others is not None and math.isfinite(check_energy):
        # the alternation solved this leg beside the others' parameters of that round: its
        # check is renewed beside their final ones, the pair the result reports
        fine = on_check_grid(at_rate)
        check_energy = (
            SwingGoal(family, settings.margins).on(fine, leg, others).energy_j(best.optimum.theta)
        )
        check_swing = SwingGoal(family).on(fine, leg).swing_energy_j(best.optimum.theta)
    return LegResult(
        leg=leg,
        best=best.optimum,
        starts=runs,
        reference_swing_energy_j=reference_swing_energy_j(at_rate, leg),
        check_energy_j=check_energy,
        sampling_error=Check(check_energy, check_swing).error(best.optimum),
        check_swing_energy_j=check_swing,
    )


def optimize_swings(
    pipeline: EnergyPipeline,
    legs: tuple[str, ...],
    family: SwingFamily,
    settings: Settings | None = None,
    theta0: Mapping[str, np.ndarray] | None = None,
    progress: Callable[[str], None] | None = None,
    stance_checked: bool = False,
    trial: bool = False,
) -> SwingOptimization:
    """Optimize ``family``'s parameters for each leg (see the module docstring).

    Args:
        pipeline: Robot, gait (its rate is the least the optimization uses), accounting.
        legs: The legs to optimize.
        family: The swing family.
        settings: Method, starts, options (default: ``scalf-opt optimize``'s).
        theta0: A first start per leg instead of the default start (label ``given``).
        progress: Called with a label as each rate and each extra start begins.
        stance_checked: The caller has already checked this gait's stance (at another rate:
            the free-trajectory bound's levels), so it is not evaluated again here.
        trial: The run is one trial of a search (a gait or a stance) started at a neighbouring
            trial's optimum ``theta0``: every solve is warm (the solver's warm strategy alone,
            :mod:`scalf_opt.optimize.solvers`), and a failed one is the trial's answer, not
            retried with the cold strategies (the search moves on); the extra starts of
            ``settings.starts`` are left to the search's answer
            (:meth:`~scalf_opt.optimize.free_stance.GaitTrials.from_every_start`).

    Raises:
        ConfigError: The family has no free parameter, or the accounting cannot be optimized.
        GaitError: The gait's stance leaves a leg's reach or joint range.
    """
    settings = settings or Settings()
    check_optimizable(family)
    check_bounded(pipeline, legs)
    for leg in () if stance_checked else legs:  # an impossible stance is the gait's error
        pipeline.stance(leg)
    start = time.perf_counter()
    first = _first_starts(pipeline, legs, family, settings, theta0)
    trial = trial and theta0 is not None and all(leg in theta0 for leg in legs)  # else cold
    rates: list[float] = []
    at_rate, answers, (rounds, settled, together), converged = _refined(
        pipeline,
        legs,
        family,
        settings,
        {leg: t for leg, (_, t) in first.items()},
        trial,
        rates,
        progress,
    )
    final = {leg: answers[leg][0].theta for leg in legs}
    results = {
        leg: _leg_result(
            at_rate,
            legs,
            leg,
            family,
            settings,
            answers[leg],
            first[leg][0],
            final,
            trial,
            progress,
        )
        for leg in legs
    }
    return SwingOptimization(
        family,
        settings,
        at_rate,
        results,
        rates,
        converged,
        time.perf_counter() - start,
        rounds,
        settled,
        together,
    )
