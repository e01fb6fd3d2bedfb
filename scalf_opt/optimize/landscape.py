"""The swing energy over a plane of parameters: the landscape a pattern search walks on.

The paper's Figure 8 shows only the path of its pattern search over (C1, C2); this module
evaluates the exact swing energy (:meth:`SwingProblem.evaluate`, the same function the optimizers
are judged by) on a grid of two parameters, the others held at a base point, and records which
points are infeasible and why.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scalf_opt.errors import ConfigError
from scalf_opt.optimize.problem import SwingProblem


@dataclass(frozen=True)
class EnergyLandscape:
    """Exact swing energy on a grid of two parameters.

    Attributes:
        leg: Leg name.
        family: Swing family name.
        axes: Indices of the two parameters varied (``theta[axes[0]]`` along ``x``).
        parameter_names: Names of those two parameters.
        unit: Their unit (``deg`` or ``cm``).
        x: Values of the first parameter, shape (nx,) [unit].
        y: Values of the second parameter, shape (ny,) [unit].
        energy_j: Exact swing energy of both joints wherever the motion exists, feasible or not,
            shape (ny, nx) [J]; NaN where the inverse kinematics fails (foot out of reach).
        feasible: Whether the point meets every constraint, shape (ny, nx).
        reasons: The first constraint each infeasible point breaks (``""`` where feasible),
            shape (ny, nx).
    """

    leg: str
    family: str
    axes: tuple[int, int]
    parameter_names: tuple[str, str]
    unit: str
    x: np.ndarray
    y: np.ndarray
    energy_j: np.ndarray
    feasible: np.ndarray
    reasons: np.ndarray

    @property
    def best(self) -> tuple[float, float, float]:
        """The lowest feasible grid point: ``(x, y, energy [J])`` (NaNs if none is feasible)."""
        masked = np.where(self.feasible, self.energy_j, np.inf)
        if not np.isfinite(masked).any():
            return (float("nan"), float("nan"), float("nan"))
        j, i = np.unravel_index(int(np.argmin(masked)), masked.shape)
        return float(self.x[i]), float(self.y[j]), float(masked[j, i])


def energy_landscape(
    problem: SwingProblem,
    x: np.ndarray,
    y: np.ndarray,
    axes: tuple[int, int] = (0, 1),
    base: np.ndarray | None = None,
) -> EnergyLandscape:
    """Evaluate the exact swing energy of ``problem`` on the grid ``x`` by ``y``.

    Args:
        problem: The leg's swing problem.
        x: Values of parameter ``axes[0]`` [family unit], shape (nx,).
        y: Values of parameter ``axes[1]`` [family unit], shape (ny,).
        axes: The two parameters varied.
        base: Values of every parameter (the two varied are overwritten); default zero.

    Raises:
        ConfigError: The family has fewer than two parameters, or ``axes`` names one it lacks.
    """
    n = problem.n_params
    if n < 2 or len(set(axes)) != 2 or not all(0 <= a < n for a in axes):
        raise ConfigError(
            f"family {problem.family.name!r} has {n} parameter(s): a landscape needs two "
            f"distinct ones, got axes {axes}"
        )
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    theta = np.zeros(n) if base is None else np.array(base, dtype=float)
    energy = np.empty((y.size, x.size))
    feasible = np.empty((y.size, x.size), dtype=bool)
    reasons = np.empty((y.size, x.size), dtype=object)
    for j, y_value in enumerate(y):
        for i, x_value in enumerate(x):
            theta[axes[0]], theta[axes[1]] = x_value, y_value
            evaluation = problem.evaluate(theta)
            feasible[j, i] = evaluation.reason is None
            reasons[j, i] = evaluation.reason or ""
            if evaluation.reason is None:
                energy[j, i] = evaluation.energy_j
            else:
                # an infeasible motion still has an energy (it shapes the contours), unless
                # the foot target is out of reach
                raw = problem.energy_j(theta)
                energy[j, i] = raw if np.isfinite(raw) else np.nan
    names = problem.family.parameter_names
    return EnergyLandscape(
        leg=problem.leg,
        family=problem.family.name,
        axes=(axes[0], axes[1]),
        parameter_names=(names[axes[0]], names[axes[1]]),
        unit=problem.family.parameter_unit,
        x=x,
        y=y,
        energy_j=energy,
        feasible=feasible,
        reasons=reasons,
    )
