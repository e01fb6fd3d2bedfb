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
from scalf_opt.energy.margins import LiftProfile

FEASIBILITY_TOLERANCE = 1e-9
"""Round-off allowed on a geometric constraint when judging a point feasible [m, rad]."""


@dataclass(frozen=True, eq=False)
class SwingGrid:
    """What a constraint family needs of the swing it bounds.

    Attributes:
        n_samples: Swing samples, lift-off and touch-down included.
        mid_index: The mid-swing sample.
        ground_z_m: The ground's height in the leg frame [m].
        clearance_z_m: The lowest foot height allowed at mid-swing, in the leg frame [m].
        phase: Each sample's swing phase, 0 at lift-off and 1 at touch-down, shape (n,).
        lift_height_m: The lift profile's height above the ground [m] (0: none).
        lift_fraction: The share of the swing the lift and the landing take.
        touchdown_speed_m_s: The largest downward foot speed over the landing [m/s].
    """

    n_samples: int
    mid_index: int
    ground_z_m: float
    clearance_z_m: float
    phase: np.ndarray
    lift_height_m: float
    lift_fraction: float
    touchdown_speed_m_s: float

    @classmethod
    def on(
        cls,
        t_s: np.ndarray,
        ground_z_m: float,
        clearance_m: float,
        lift: LiftProfile,
    ) -> SwingGrid:
        """The grid of a swing sampled at times ``t_s`` (from lift-off) [s], ground and H [m]."""
        duration = float(t_s[-1] - t_s[0])
        return cls(
            n_samples=int(t_s.size),
            mid_index=(int(t_s.size) - 1) // 2,
            ground_z_m=ground_z_m,
            clearance_z_m=ground_z_m + clearance_m,
            phase=(t_s - t_s[0]) / duration,
            lift_height_m=lift.height_for(clearance_m),
            lift_fraction=lift.fraction,
            touchdown_speed_m_s=lift.touchdown_speed_for(clearance_m, duration),
        )

    def lift_z_m(self) -> np.ndarray:
        """The lift profile's lowest foot height at each sample, in the leg frame [m].

        ``height * (min(s, 1 - s) / fraction)**2`` above the ground, capped at the height: the
        foot rises at least as fast as a constant acceleration that takes it to the height at
        the lift fraction, and lands mirrored.
        """
        ramp = np.minimum(np.minimum(self.phase, 1.0 - self.phase) / self.lift_fraction, 1.0)
        return self.ground_z_m + self.lift_height_m * ramp**2

    def landing(self) -> np.ndarray:
        """Which samples lie in the landing, the last lift fraction of the swing."""
        return self.phase >= 1.0 - self.lift_fraction - 1e-12


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
    """The foot on or above its lift profile at every interior sample, H up at mid-swing.

    The lift profile (:class:`~scalf_opt.energy.margins.LiftProfile`, :meth:`SwingGrid.lift_z_m`)
    keeps the foot off the ground it would otherwise skim at lift-off and touch-down; with no
    lift height the bound is the ground itself. The end samples are on the ground by
    construction.
    """

    def bounds(self, grid: SwingGrid) -> tuple[np.ndarray, np.ndarray]:  # noqa: D102
        lower, upper = super().bounds(grid)
        lower[1:-1] = np.maximum(grid.lift_z_m()[1:-1], grid.ground_z_m)
        lower[grid.mid_index] = max(grid.clearance_z_m, lower[grid.mid_index])
        return lower, upper

    def reason(self, sample: int, grid: SwingGrid) -> str:  # noqa: D102
        if sample == grid.mid_index:
            return "mid-swing clearance"
        if grid.lift_height_m > 0:
            return (
                f"foot below its lift profile ({1e3 * grid.lift_height_m:.3g} mm up by "
                f"{100 * grid.lift_fraction:g} % of the swing)"
            )
        return "foot below ground"


@dataclass(frozen=True)
class LandingSpeed(ConstraintFamily):
    """The foot comes down no faster than the touch-down speed over the landing.

    The landing is the last lift fraction of the swing; a foot that arrives fast meets the
    ground hard when the servo's lag moves the touch-down a few milliseconds earlier.
    """

    def bounds(self, grid: SwingGrid) -> tuple[np.ndarray, np.ndarray]:  # noqa: D102
        lower, upper = super().bounds(grid)
        if np.isfinite(grid.touchdown_speed_m_s):
            lower[grid.landing()] = -grid.touchdown_speed_m_s
        return lower, upper

    def reason(self, sample: int, grid: SwingGrid) -> str:  # noqa: D102
        return f"foot lands faster than {grid.touchdown_speed_m_s:.3g} m/s"


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
