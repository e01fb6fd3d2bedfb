"""The swing problem's constraints as families: one per kernel row, each with its samples,
bounds, round-off and reason."""

import numpy as np
import pytest

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.constraints import (
    FEASIBILITY_TOLERANCE,
    GroundClearance,
    LeavesFromAbove,
    LimitRows,
    Reach,
)
from scalf_opt.optimize.problem import SwingProblem


@pytest.mark.parametrize("family", ["joint-6", "fourier-4"])
def test_each_kernel_row_has_its_family_and_bounds(scalf, family):
    problem = SwingProblem(EnergyPipeline(scalf, Gait(), loads="trunk"), "RF", make_family(family))
    kinds = [type(f) for f in problem.constraints]
    n_limits = len(problem.bounds)
    assert kinds[:n_limits] == [LimitRows] * n_limits
    assert kinds[n_limits:] == [GroundClearance, LeavesFromAbove] + (
        [Reach] if family.startswith("fourier") else []
    )
    lower, upper = problem.constraint_bounds
    grid = problem.grid
    z = problem.kernel.row("foot_z")
    assert np.isneginf(lower[z, [0, -1]]).all()
    assert lower[z, 1] == grid.ground_z_m == -Gait().stance_height_m
    assert lower[z, grid.mid_index] == pytest.approx(grid.ground_z_m + Gait().clearance_m, 1e-15)
    accel = problem.kernel.row("foot_z_accel")
    assert (lower[accel, [0, -1]] == 0.0).all() and np.isneginf(lower[accel, 1:-1]).all()
    for i, b in enumerate(problem.bounds):
        assert (lower[i] == b.lower).all() and (upper[i] == b.upper).all()
        assert problem.constraint_tolerance[i, 0] == b.tolerance()
    assert problem.constraint_tolerance[z, 0] == FEASIBILITY_TOLERANCE


def test_a_crossing_is_told_by_its_familys_reason(scalf):
    problem = SwingProblem(EnergyPipeline(scalf, Gait(), loads="trunk"), "RF", make_family("paper"))
    z = problem.kernel.row("foot_z")
    grid = problem.grid
    assert problem.constraints[z].reason(grid.mid_index, grid) == "mid-swing clearance"
    assert problem.constraints[z].reason(1, grid) == "foot below ground"
    assert problem.constraints[0].reason(3, grid).endswith(problem.bounds[0].source)
    # members that cross a limit, or leave the ground from below: the evaluation says which
    assert problem.evaluate(np.array([0.0, -30.0])).reason == (
        "qd_knee beyond its URDF velocity limit"
    )
    assert problem.evaluate(np.array([30.0, 0.0])).reason == (
        "foot leaves or meets the ground from below"
    )
