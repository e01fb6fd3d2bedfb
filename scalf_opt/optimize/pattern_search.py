"""Hooke-Jeeves pattern search, as the paper uses it (Section 6.1, Figure 8).

Exploratory move: from the current point, try ``+step_i`` then ``-step_i`` along each coordinate
in turn and keep every improvement. Pattern move: after a successful exploration from base ``b``
to ``x``, jump to ``x + alpha (x - b)`` (acceleration coefficient ``alpha``) and explore there;
keep jumping while that improves. When an exploration around the base fails, every step is
multiplied by the shrinkage coefficient ``beta``. The search stops when every step is below the
precision. The paper's settings: start (0, 0), step (0.5, 0.5), precision 0.1; its ``alpha`` and
``beta`` were lost, and the textbook values ``alpha = 1``, ``beta = 0.5`` are the defaults here.

Infeasible points (``objective`` returns ``(inf, reason)``) are worse than any feasible point; the
reasons are counted. Only strict improvements are accepted, so the result is never worse than the
start.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from scalf_opt.interrupts import raise_if_stopped

Objective = Callable[[np.ndarray], tuple[float, str | None]]
"""Maps parameters to ``(value, None)`` or ``(inf, reason)`` for an infeasible point."""


@dataclass(frozen=True)
class PatternSearchOptions:
    """Settings of :func:`pattern_search` (defaults: the paper's, plus textbook alpha, beta).

    Attributes:
        initial_step: Initial step per coordinate (a scalar applies to all).
        precision: Stop when every step is below this.
        acceleration: Pattern-move coefficient alpha (> 0).
        shrinkage: Step reduction factor beta in (0, 1).
        max_evaluations: Safety limit on objective evaluations.
        target: Stop as soon as a value at or below this is found (None: run to precision).
    """

    initial_step: float | tuple[float, ...] = 0.5
    precision: float = 0.1
    acceleration: float = 1.0
    shrinkage: float = 0.5
    max_evaluations: int = 100_000
    target: float | None = None

    def __post_init__(self) -> None:
        steps = np.atleast_1d(np.asarray(self.initial_step, dtype=float))
        if not np.all(steps > 0):
            raise ValueError(f"initial_step must be > 0, got {self.initial_step!r}")
        if not self.precision > 0:
            raise ValueError(f"precision must be > 0, got {self.precision!r}")
        if not self.acceleration > 0:
            raise ValueError(f"acceleration must be > 0, got {self.acceleration!r}")
        if not 0 < self.shrinkage < 1:
            raise ValueError(f"shrinkage must be in (0, 1), got {self.shrinkage!r}")


@dataclass
class PatternSearchResult:
    """Outcome of a pattern search.

    Attributes:
        x: Best point found.
        value: Objective at ``x``.
        iterations: Number of exploratory moves around a base point (successful or not).
        evaluations: Number of objective evaluations.
        history: One row per accepted base point: (iteration, *x, value) (the paper's Fig. 8).
        infeasible: Count of infeasible evaluations per reason.
        converged: True if the step fell below the precision (False: evaluation limit hit).
    """

    x: np.ndarray
    value: float
    iterations: int
    evaluations: int
    history: list[tuple[float, ...]] = field(default_factory=list)
    infeasible: Counter[str] = field(default_factory=Counter)
    converged: bool = True


def pattern_search(
    objective: Objective,
    x0: np.ndarray,
    options: PatternSearchOptions | None = None,
) -> PatternSearchResult:
    """Minimise ``objective`` from ``x0`` by Hooke-Jeeves pattern search."""
    opts = options or PatternSearchOptions()
    x0 = np.asarray(x0, dtype=float)
    step = np.broadcast_to(np.asarray(opts.initial_step, dtype=float), x0.shape).copy()
    counts: Counter[str] = Counter()
    n_eval = 0

    def f(x: np.ndarray) -> float:
        nonlocal n_eval
        n_eval += 1
        value, reason = objective(x)
        if reason is not None or not math.isfinite(value):
            counts[reason or "non-finite objective"] += 1
            return math.inf
        return value

    def explore(x: np.ndarray, fx: float) -> tuple[np.ndarray, float]:
        x = x.copy()
        for i in range(x.size):
            for sign in (1.0, -1.0):
                trial = x.copy()
                trial[i] += sign * step[i]
                ft = f(trial)
                if ft < fx:
                    x, fx = trial, ft
                    break
        return x, fx

    base, f_base = x0.copy(), f(x0)
    iterations = 0
    history: list[tuple[float, ...]] = [(0, *base, f_base)]

    def reached() -> bool:
        return opts.target is not None and f_base <= opts.target

    while np.any(step >= opts.precision) and not reached():
        if n_eval >= opts.max_evaluations:
            return PatternSearchResult(base, f_base, iterations, n_eval, history, counts, False)
        iterations += 1
        raise_if_stopped()
        x_new, f_new = explore(base, f_base)
        if f_new < f_base:
            while True:
                pattern = x_new + opts.acceleration * (x_new - base)
                base, f_base = x_new, f_new
                history.append((iterations, *base, f_base))
                if reached():
                    break
                x_try, f_try = explore(pattern, f(pattern))
                if f_try < f_base:
                    x_new, f_new = x_try, f_try
                    iterations += 1
                else:
                    break
        else:
            step *= opts.shrinkage
    return PatternSearchResult(base, f_base, iterations, n_eval, history, counts, True)
