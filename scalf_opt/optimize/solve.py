"""The two optimizers on a :class:`SwingProblem`, returning one result type.

The registry that chooses between them is :mod:`scalf_opt.optimize.solvers`. Both answers are
evaluated with the exact, non-smooth swing energy of
:meth:`SwingProblem.evaluate`, whatever the optimizer minimised internally.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from scalf_opt.optimize.nlp import NlpSolution, build_nlp, solve_nlp
from scalf_opt.optimize.pattern_search import (
    PatternSearchOptions,
    PatternSearchResult,
    pattern_search,
)
from scalf_opt.optimize.problem import PairProblem, SwingProblem
from scalf_opt.optimize.screening import rows_far_from_bounds, strictly_inside
from scalf_opt.types import Method

History = tuple[tuple[float, ...], ...]
"""Rows ``(iteration, *theta, value)`` of a pattern search's accepted points."""


@dataclass(frozen=True)
class PatternSearchDetails:
    """What the pattern search reports beyond the common answer.

    Attributes:
        evaluations: Objective evaluations (of both phases).
        history: Rows (iteration, *theta, energy) of accepted points; in
            :func:`scalf_opt.io.optimization_records.optimum_record` records with named parameters.
        feasibility_history: From an infeasible start: rows (iteration, *theta, total
            constraint violation) of the feasibility phase's accepted points (empty when the
            start is feasible).
        infeasible: Count of infeasible evaluations per reason.
        feasibility_phase_iterations: Iterations of the feasibility phase (0 without one).
    """

    evaluations: int
    history: History = ()
    feasibility_history: History = ()
    infeasible: Mapping[str, int] = field(default_factory=dict)
    feasibility_phase_iterations: int = 0

    def solver_stats(self) -> dict[str, Any]:
        """The statistics of ``solver_stats`` in the JSON record."""
        return {"feasibility_phase_iterations": self.feasibility_phase_iterations}


@dataclass(frozen=True)
class IpoptDetails:
    """What Ipopt reports beyond the common answer.

    Attributes:
        stats: Ipopt's statistics as CasADi returns them, with ``smooth_objective_j`` (the
            smoothed objective at the answer [J]), ``solver_time_s`` and ``rows_left_out``
            (the rows screening left out, comma-separated; empty when none was).
    """

    stats: Mapping[str, Any]


SolverDetails = PatternSearchDetails | IpoptDetails
"""The solver-specific part of a :class:`SwingOptimum`."""


@dataclass(frozen=True)
class SwingOptimum:
    """The answer of one optimizer for one leg and family.

    Attributes:
        leg: Leg name.
        family: Swing family name.
        method: ``pattern`` or ``ipopt``.
        theta: Parameters found (family units, see ``unit``).
        parameter_names: Names of the parameters.
        unit: Unit of the parameters (``deg`` or ``cm``).
        swing_energy_j: Exact swing energy at ``theta`` [J] (inf if infeasible).
        success: The optimizer converged to a feasible point.
        status: The optimizer's own status text.
        iterations: Iterations (pattern search: exploratory moves of both phases; Ipopt: its
            iteration count).
        wall_time_s: Time spent [s].
        details: What the solver reports beyond this (:data:`SolverDetails`).
        objective_j: The exact objective at ``theta`` [J]: ``swing_energy_j`` plus, under
            whole-body loads, the pair's stance energy (:class:`SwingProblem`); inf if
            infeasible.
    """

    leg: str
    family: str
    method: Method
    theta: np.ndarray
    parameter_names: list[str]
    unit: str
    swing_energy_j: float
    success: bool
    status: str
    iterations: int
    wall_time_s: float
    details: SolverDetails
    objective_j: float = math.nan

    @property
    def evaluations(self) -> int:
        """Objective evaluations (pattern search) or 0 (Ipopt evaluates its NLP, not these)."""
        return self.details.evaluations if isinstance(self.details, PatternSearchDetails) else 0

    @property
    def pattern_details(self) -> PatternSearchDetails:
        """The pattern search's details (its history, for the paper's Fig. 8).

        Raises:
            TypeError: The answer is another solver's.
        """
        if not isinstance(self.details, PatternSearchDetails):
            raise TypeError(f"the {self.method} answer of {self.leg} has no pattern-search details")
        return self.details


def run_pattern_search(
    problem: SwingProblem,
    x0: np.ndarray | None = None,
    options: PatternSearchOptions | None = None,
) -> SwingOptimum:
    """The paper's pattern search, in two phases when the start is infeasible.

    Phase 1 (only if ``x0`` is infeasible) minimises the total constraint violation with the same
    settings until it reaches zero; phase 2 minimises the exact swing energy from there.
    """
    opts = options or PatternSearchOptions()
    x0 = np.zeros(problem.n_params) if x0 is None else np.asarray(x0, dtype=float)
    start = time.perf_counter()

    def energy(theta: np.ndarray) -> tuple[float, str | None]:
        e = problem.evaluate(theta)
        return e.energy_j, e.reason

    def violation(theta: np.ndarray) -> tuple[float, str | None]:
        return problem.violation(theta), None

    phase1: PatternSearchResult | None = None
    if problem.evaluate(x0).reason is not None:
        phase1 = pattern_search(violation, x0, _with_target(opts, 0.0))
        if phase1.value > 0.0:
            return _pattern_optimum(
                problem, phase1, phase1, time.perf_counter() - start, "no feasible point found"
            )
        x0 = phase1.x
    result = pattern_search(energy, x0, opts)
    status = "converged: step below precision" if result.converged else "evaluation limit"
    return _pattern_optimum(problem, result, phase1, time.perf_counter() - start, status)


def _swing_energy_j(problem: SwingProblem, theta: np.ndarray, objective_j: float) -> float:
    """The leg's own swing energy at a point whose objective is ``objective_j`` (inf: inf)."""
    if not problem.couplings or not math.isfinite(objective_j):
        return objective_j
    return problem.swing_energy_j(theta)


def _with_target(opts: PatternSearchOptions, target: float) -> PatternSearchOptions:
    return PatternSearchOptions(
        opts.initial_step,
        opts.precision,
        opts.acceleration,
        opts.shrinkage,
        opts.max_evaluations,
        target,
    )


def _pattern_optimum(
    problem: SwingProblem,
    result: PatternSearchResult,
    phase1: PatternSearchResult | None,
    elapsed: float,
    status: str,
) -> SwingOptimum:
    final = problem.evaluate(result.x)
    feasible = final.reason is None and (phase1 is None or phase1.value == 0.0)
    before = phase1 if phase1 is not None and phase1 is not result else None
    shift = before.iterations if before is not None else 0
    details = PatternSearchDetails(
        evaluations=result.evaluations + (before.evaluations if before else 0),
        history=tuple((row[0] + shift, *row[1:]) for row in result.history),
        feasibility_history=tuple(phase1.history) if phase1 is not None else (),
        infeasible={**result.infeasible, **(before.infeasible if before else {})},
        feasibility_phase_iterations=phase1.iterations if phase1 else 0,
    )
    return SwingOptimum(
        leg=problem.leg,
        family=problem.family.name,
        method="pattern",
        theta=result.x,
        parameter_names=problem.family.parameter_names,
        unit=problem.family.parameter_unit,
        swing_energy_j=_swing_energy_j(problem, result.x, final.energy_j),
        objective_j=final.energy_j,
        success=feasible and result.converged,
        status=status,
        iterations=result.iterations + shift,
        wall_time_s=elapsed,
        details=details,
    )


def run_ipopt(
    problem: SwingProblem,
    theta0: np.ndarray | None = None,
    ipopt_options: dict[str, Any] | None = None,
    screen: bool = False,
) -> SwingOptimum:
    """Solve the smooth NLP with Ipopt and evaluate its answer exactly.

    ``success`` is True only if Ipopt reports a solved problem *and* the exact evaluation finds
    the answer feasible.

    With ``screen``, the rows far inside their bounds at ``theta0`` are left out of the NLP
    (:mod:`scalf_opt.optimize.screening`); an answer that is not a feasible, solved point of the
    whole problem with the rows left out strictly inside their bounds is discarded and the
    problem solved again, from ``theta0``, with every row (the time of both solves is the
    answer's). Its statistics name the rows left out (``rows_left_out``, empty when none was or
    the second solve answered).
    """
    theta0 = np.zeros(problem.n_params) if theta0 is None else np.asarray(theta0, dtype=float)
    start = time.perf_counter()
    left_out = rows_far_from_bounds(problem, theta0) if screen else ()
    if left_out:
        screened = _run_ipopt(problem, theta0, ipopt_options, left_out, start)
        if screened.success and strictly_inside(problem, screened.theta, left_out):
            return screened
    return _run_ipopt(problem, theta0, ipopt_options, (), start)


def _run_ipopt(
    problem: SwingProblem,
    theta0: np.ndarray,
    ipopt_options: dict[str, Any] | None,
    left_out: tuple[int, ...],
    start: float,
) -> SwingOptimum:
    """One Ipopt solve of ``problem`` without the rows ``left_out``, evaluated with every row."""
    built = build_nlp(problem, ipopt_options, left_out)
    solution = solve_nlp(built, problem, theta0)
    rows = ",".join(problem.kernel.rows[row] for row in left_out)
    return _ipopt_optimum(problem, solution.theta, solution, time.perf_counter() - start, rows)


def run_ipopt_pair(
    problem: PairProblem,
    thetas0: Mapping[str, np.ndarray],
    ipopt_options: dict[str, Any] | None = None,
) -> dict[str, SwingOptimum]:
    """Solve both legs of ``problem`` in one NLP with Ipopt; each leg's answer evaluated exactly.

    Each leg's answer is evaluated on its own problem with the other leg's answer fixed
    (:meth:`PairProblem.leg_problem`), as a leg solved alone would be: its objective is its
    swing energy plus the pair's stance energy. ``success`` is True for both only if Ipopt
    reports a solved problem and every leg's answer is feasible.
    """
    start = time.perf_counter()
    built = build_nlp(problem, ipopt_options)
    solution = solve_nlp(built, problem, [thetas0[leg] for leg in problem.legs])
    elapsed = time.perf_counter() - start
    thetas = dict(zip(problem.legs, solution.thetas, strict=True))
    answers = {
        leg: _ipopt_optimum(problem.leg_problem(leg, thetas), thetas[leg], solution, elapsed, "")
        for leg in problem.legs
    }
    if not all(a.success for a in answers.values()):  # the pair's answer fails as a whole
        answers = {
            leg: replace(a, success=False, status=f"{a.status}; the other leg's answer failed")
            if a.success
            else a
            for leg, a in answers.items()
        }
    return answers


def _ipopt_optimum(
    problem: SwingProblem, theta: np.ndarray, solution: NlpSolution, elapsed: float, rows: str
) -> SwingOptimum:
    """The answer ``theta`` of an Ipopt solve, evaluated exactly on ``problem``."""
    final = problem.evaluate(theta)
    stats = dict(solution.stats)
    stats["smooth_objective_j"] = solution.objective_j
    stats["solver_time_s"] = solution.wall_time_s
    stats["rows_left_out"] = rows
    return SwingOptimum(
        leg=problem.leg,
        family=problem.family.name,
        method="ipopt",
        theta=theta,
        parameter_names=problem.family.parameter_names,
        unit=problem.family.parameter_unit,
        swing_energy_j=_swing_energy_j(problem, theta, final.energy_j),
        objective_j=final.energy_j,
        success=solution.success and final.reason is None,
        status=solution.status if final.reason is None else f"{solution.status}; {final.reason}",
        iterations=solution.iterations,
        wall_time_s=elapsed,
        details=IpoptDetails(stats),
    )
