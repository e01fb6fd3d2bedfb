"""The swing solvers behind one protocol, and their registry.

A solver takes a :class:`~scalf_opt.optimize.problem.SwingProblem` (one leg, one family, one
sample grid), a start and the :class:`SolverOptions`, and returns a
:class:`~scalf_opt.optimize.solve.SwingOptimum` whose energy is the exact one, whatever the solver
minimised internally. It also says where its first start is (:meth:`SwingSolver.default_start`)
and, for a solver with several strategies, tries them in turn until one converges. A *warm*
solve (a search's trial, started at a neighbouring problem's optimum) uses the solver's warm
strategy alone, and its failure is final: the search moves on.

Everything above this floor asks the registry (:data:`SOLVERS`, :func:`solver`): the command
line's ``--method`` choices and help, the study files, the driver. A new solver is one class (in
its own module, or here) and one line in :data:`SOLVERS`.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, ClassVar, TypeVar

import numpy as np

from scalf_opt.errors import ConfigError
from scalf_opt.optimize.pattern_search import PatternSearchOptions

if TYPE_CHECKING:  # the registry's names load without CasADi and Pinocchio (the command line)
    from scalf_opt.optimize.problem import PairProblem, SwingProblem
    from scalf_opt.optimize.solve import SwingOptimum


@dataclass(frozen=True)
class SolverOptions:
    """Options of the solvers (each reads its own).

    Attributes:
        pattern: The pattern search's settings (the paper's by default).
        ipopt: Extra Ipopt options set by the user (``{"print_level": 5}``: its log), or None.
        screen: Ipopt leaves out of its NLP the rows far inside their bounds at the start and
            solves again with every row unless its answer keeps them strictly inside
            (:mod:`scalf_opt.optimize.screening`): for starts near the optimum.
        first_strategy_iterations: Ipopt's first strategy (the adaptive barrier update) gives
            way to the next after this many iterations instead of its own 1000: for a solve
            whose answer only starts another (:data:`FIRST_ROUND_ITERATIONS`); None: no cap.
    """

    pattern: PatternSearchOptions = field(default_factory=PatternSearchOptions)
    ipopt: dict[str, Any] | None = None
    screen: bool = False
    first_strategy_iterations: int | None = None


class SwingSolver(ABC):
    """One way to minimise a swing problem's exact energy under its constraints."""

    name: ClassVar[str]
    description: ClassVar[str]
    releases_gil: ClassVar[bool] = False
    """It spends its time in native code that releases Python's GIL, so legs may be solved on
    parallel threads. (Ipopt does, but its MUMPS runs one factorization at a time per process:
    two SCalf legs' ``joint-6`` solves take the same 0.36 s on one thread or two; the large
    solves of the free-trajectory bound run in worker processes instead.)"""
    solves_pairs: ClassVar[bool] = False
    """It takes a whole-body pair as one problem (:meth:`solve_pair`)."""

    @abstractmethod
    def solve(
        self,
        problem: SwingProblem,
        theta0: np.ndarray,
        options: SolverOptions,
        warm: bool = False,
    ) -> SwingOptimum:
        """Minimise from ``theta0`` (family units); the answer evaluated exactly.

        ``warm``: ``theta0`` is a neighbouring problem's optimum and the solve one trial of a
        search; the solver uses its warm strategy alone and does not retry when it fails.
        """

    def solve_pair(
        self,
        problem: PairProblem,
        thetas0: Mapping[str, np.ndarray],
        options: SolverOptions,
        warm: bool = False,
    ) -> dict[str, SwingOptimum]:
        """Minimise both legs of a pair together, from ``thetas0``; each answer evaluated exactly.

        Only for a solver that :attr:`solves_pairs`; with any other the driver optimizes the
        pair's legs in turn until they settle.
        """
        raise NotImplementedError(f"{self.name} cannot take a pair as one problem")

    def default_start(self, problem: SwingProblem) -> str:
        """Where the first start is: ``zero`` or ``closest to the reference``."""
        return "zero"


class PatternSearchSolver(SwingSolver):
    """The paper's Hooke-Jeeves pattern search on the exact energy (two phases if infeasible)."""

    name = "pattern"
    description = "the paper's pattern search"

    def solve(  # noqa: D102
        self,
        problem: SwingProblem,
        theta0: np.ndarray,
        options: SolverOptions,
        warm: bool = False,
    ) -> SwingOptimum:
        from scalf_opt.optimize.solve import run_pattern_search

        return run_pattern_search(problem, theta0, options.pattern)

    def default_start(self, problem: SwingProblem) -> str:
        """The paper's start (0, 0) on the paper family, else the member closest to the reference.

        A search with many parameters and small steps begins where the reference is, not at an
        arbitrary member.
        """
        return "zero" if problem.family.name == "paper" else "closest to the reference"


IPOPT_ATTEMPTS: tuple[dict[str, Any], ...] = (
    {"max_iter": 1000},
    {"mu_strategy": "monotone", "max_iter": 1000},
    {"mu_strategy": "monotone", "nlp_scaling_method": "none", "max_iter": 3000},
)
"""Ipopt's strategies, tried in turn from the same start until one converges. The adaptive
barrier update (Ipopt's options in :mod:`scalf_opt.optimize.nlp`) is the fastest; on optima
riding actuator limits (HyQ's cylinders at their 1960 N pull, foot-space families of order 5
and more) it can wander for thousands of iterations where the monotone update converges in a
few hundred, and HyQ's ``fourier-12`` (RF) converges only without Ipopt's gradient-based
scaling. Options the user sets win; a strategy that would change one of them is skipped."""

FIRST_ROUND_ITERATIONS = 300
"""Ipopt's first strategy's iterations in the solves that only start a whole-body pair's problem
(:func:`scalf_opt.optimize.driver.optimize_swings`' first round of the legs in turn). On the six
robots' default pairs those solves take 34 to 186 iterations; on a Go1 gait the adaptive update
wandered through all 1000 of one leg's where the monotone one, tried next, converged in 111
(the measurement: docs/speed-log.md, "Measurements behind choices")."""

IPOPT_WARM_ATTEMPT: dict[str, Any] = {"max_iter": 1000, "mu_max": 0.1}
"""Ipopt's strategy for a warm solve: the adaptive barrier update, its parameter never above
its initial 0.1. A warm start is a neighbouring problem's optimum: raising the barrier
parameter only pushes it away from its active bounds. Near a limit a search's trials are
often (nearly) infeasible, and there the uncapped update diverged; capped, a gait search's
speed took half the time and the free stance fewer iterations for the same stance
(measured: docs/speed-log.md, "Measurements behind choices")."""


class IpoptSolver(SwingSolver):
    """The smooth NLP (:mod:`scalf_opt.optimize.nlp`) solved by Ipopt, with its retry strategies."""

    name = "ipopt"
    description = "the smooth NLP solved by Ipopt (exact derivatives)"
    releases_gil = True  # CasADi releases it while Ipopt runs
    solves_pairs = True  # one NLP over both legs' swings

    def solve(  # noqa: D102
        self,
        problem: SwingProblem,
        theta0: np.ndarray,
        options: SolverOptions,
        warm: bool = False,
    ) -> SwingOptimum:
        from scalf_opt.optimize.solve import run_ipopt

        return _with_retries(
            lambda attempt: run_ipopt(problem, theta0, attempt, options.screen),
            lambda answer: answer.success,
            options,
            warm,
        )

    def solve_pair(  # noqa: D102
        self,
        problem: PairProblem,
        thetas0: Mapping[str, np.ndarray],
        options: SolverOptions,
        warm: bool = False,
    ) -> dict[str, SwingOptimum]:
        from scalf_opt.optimize.solve import run_ipopt_pair

        return _with_retries(
            lambda attempt: run_ipopt_pair(problem, thetas0, attempt),
            lambda answers: all(a.success for a in answers.values()),
            options,
            warm,
        )


Answer = TypeVar("Answer")


def _with_retries(
    run: Callable[[dict[str, Any]], Answer],
    solved: Callable[[Answer], bool],
    options: SolverOptions,
    warm: bool,
) -> Answer:
    """Ipopt's strategies in turn (:data:`IPOPT_ATTEMPTS`, or the warm one) until one solves."""
    user = options.ipopt or {}
    answer: Answer | None = None
    attempts = IPOPT_ATTEMPTS
    if options.first_strategy_iterations is not None:
        attempts = ({**attempts[0], "max_iter": options.first_strategy_iterations}, *attempts[1:])
    for attempt in (IPOPT_WARM_ATTEMPT,) if warm else attempts:
        if answer is not None and any(key in user for key in attempt if key != "max_iter"):
            continue  # the user chose that option: no other strategy is tried for it
        answer = run({**attempt, **user})
        if solved(answer):
            break
    assert answer is not None
    return answer


SOLVERS: dict[str, SwingSolver] = {s.name: s for s in (IpoptSolver(), PatternSearchSolver())}
"""Every solver by name; the first is the default."""

DEFAULT_SOLVER = next(iter(SOLVERS))


def solver(name: str) -> SwingSolver:
    """The solver called ``name``.

    Raises:
        ConfigError: No solver has that name; the message lists the choices.
    """
    if name not in SOLVERS:
        raise ConfigError(f"method = {name!r} is not one of {', '.join(SOLVERS)}", field="method")
    return SOLVERS[name]


def solver_help() -> str:
    """One phrase per solver for ``--help``: ``ipopt (default): ..., pattern: ...``."""
    parts = [
        f"{name}{' (default)' if name == DEFAULT_SOLVER else ''}: {s.description}"
        for name, s in SOLVERS.items()
    ]
    return "; ".join(parts)
