"""The constraints of a swing problem, as families of rows.

A family says which kernel row it bounds, at which samples, within which bounds, to which
round-off, and the reason a crossing gives.

A swing problem (:class:`~scalf_opt.optimize.problem.SwingProblem`) bounds the rows of its
leg's kernel (:mod:`scalf_opt.optimize.kernels`) at the swing samples. Each row belongs to one
family here; the problem assembles the families' bounds into the ``(rows, samples)`` arrays
both solvers use (the NLP's constraint bounds, the exact evaluation's feasibility) and asks the
family of the row that fails first for the reason it reports. A new kind of constraint on the
swing (a kernel row) is one more family.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scalf_opt.energy.limits import Bound

FEASIBILITY_TOLERANCE = 1e-9
"""Round-off allowed on a geometric constraint when judging a point feasible [m, rad]."""


@dataclass(frozen=True)
class SwingGrid:
    """What a constraint family needs of the swing it bounds.

    Attributes:
        n_samples: Swing samples, lift-off and touch-down included.
        mid_index: The mid-swing sample.
        ground_z_m: The ground's height in the leg frame [m].
        clearance_z_m: The lowest foot height allowed at mid-swing, in the leg frame [m].
    """

    n_samples: int
    mid_index: int
    ground_z_m: float
    clearance_z_m: float


@dataclass(frozen=True)
class ConstraintFamily:
    """One kernel row's constraint at the swing samples (the base: a box on every sample).

    Attributes:
        row: The kernel row's name (:attr:`~scalf_opt.optimize.kernels.Kernel.rows`).
    """

    row: str

    def bounds(self, grid: SwingGrid) -> tuple[np.ndarray, np.ndarray]:
        """Lower and upper bounds at every sample, shape (n,) each (``-inf``/``inf``: none)."""
        return np.full(grid.n_samples, -np.inf), np.full(grid.n_samples, np.inf)

    def tolerance(self) -> float:
        """Round-off allowed beyond the bounds when a point is judged feasible (row's unit)."""
        return FEASIBILITY_TOLERANCE

    def reason(self, sample: int, grid: SwingGrid) -> str:
        """Why a point that crosses this row at ``sample`` is infeasible, in words."""
        return f"{self.row} beyond its bounds"


@dataclass(frozen=True)
class LimitRows(ConstraintFamily):
    """A limit of the leg (joint range, velocity, effort, a drive's) at every sample.

    Attributes:
        bound: The limit, the problem's margins applied.
    """

    bound: Bound

    def bounds(self, grid: SwingGrid) -> tuple[np.ndarray, np.ndarray]:  # noqa: D102
        n = grid.n_samples
        return np.full(n, self.bound.lower), np.full(n, self.bound.upper)

    def tolerance(self) -> float:  # noqa: D102
        return self.bound.tolerance()

    def reason(self, sample: int, grid: SwingGrid) -> str:  # noqa: D102
        return f"{self.bound.name} beyond its {self.bound.source}"


@dataclass(frozen=True)
class GroundClearance(ConstraintFamily):
    """The foot at or above the ground at every interior sample, H above it at mid-swing.

    The end samples are on the ground by construction.
    """

    def bounds(self, grid: SwingGrid) -> tuple[np.ndarray, np.ndarray]:  # noqa: D102
        lower, upper = super().bounds(grid)
        lower[1:-1] = grid.ground_z_m
        lower[grid.mid_index] = grid.clearance_z_m
        return lower, upper

    def reason(self, sample: int, grid: SwingGrid) -> str:  # noqa: D102
        return "mid-swing clearance" if sample == grid.mid_index else "foot below ground"


@dataclass(frozen=True)
class LeavesFromAbove(ConstraintFamily):
    """The foot's vertical acceleration >= 0 at lift-off and touch-down.

    There the foot is on the ground at rest vertically: without it the foot could dip below
    the ground between the first samples.
    """

    def bounds(self, grid: SwingGrid) -> tuple[np.ndarray, np.ndarray]:  # noqa: D102
        lower, upper = super().bounds(grid)
        lower[[0, -1]] = 0.0
        return lower, upper

    def reason(self, sample: int, grid: SwingGrid) -> str:  # noqa: D102
        return "foot leaves or meets the ground from below"


@dataclass(frozen=True)
class Reach(ConstraintFamily):
    """In foot space, the foot target inside the leg's reach (the row's cosine in [-1, 1])."""

    def bounds(self, grid: SwingGrid) -> tuple[np.ndarray, np.ndarray]:  # noqa: D102
        n = grid.n_samples
        return np.full(n, -1.0), np.full(n, 1.0)

    def reason(self, sample: int, grid: SwingGrid) -> str:  # noqa: D102
        return "foot target out of reach"
