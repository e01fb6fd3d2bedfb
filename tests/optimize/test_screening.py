"""Constraint screening: a warm solve leaves out the rows far from their bounds, and its answer
is still an answer of the whole problem (the free-trajectory bound's 32-span level of SCalf's
RF leg, started at the 16-span optimum)."""

import time

import numpy as np
import pytest

import scalf_opt.optimize.solve as solve_module
from scalf_opt.energy.loads import PAPER_LOADS
from scalf_opt.energy.margins import NO_LIFT_PROFILE, LimitMargins
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.bspline import BSplineFamily
from scalf_opt.optimize.bound import WARM_START_OPTIONS, _projection, level_rate_hz
from scalf_opt.optimize.problem import SwingProblem
from scalf_opt.optimize.sampling import with_rate
from scalf_opt.optimize.screening import rows_far_from_bounds, strictly_inside
from scalf_opt.optimize.solve import run_ipopt
from scalf_opt.optimize.starts import closest_member, reference_path

pytestmark = pytest.mark.xdist_group("screening")


def _level(pipeline: EnergyPipeline, spans: int) -> EnergyPipeline:
    return pipeline.with_gait(with_rate(pipeline.gait, level_rate_hz(pipeline.gait, spans)))


@pytest.fixture(scope="module")
def warm(scalf):
    """The 32-span problem and its start at the 16-span optimum."""
    pipeline = EnergyPipeline(scalf, Gait()).with_loads(PAPER_LOADS)
    # the actuator rows the screen leaves out, and the ground's, as they were written for
    margins = LimitMargins(effort_share=0.0, lift=NO_LIFT_PROFILE)
    coarse = SwingProblem(_level(pipeline, 16), "RF", BSplineFamily(16), margins=margins)
    optimum = run_ipopt(coarse, closest_member(coarse, reference_path(coarse)))
    assert optimum.success
    level = _level(pipeline, 32)
    problem = SwingProblem(level, "RF", BSplineFamily(32), margins=margins)
    return problem, _projection(level, "RF", BSplineFamily(32), BSplineFamily(16), optimum.theta)


@pytest.fixture(scope="module")
def whole(warm):
    problem, theta0 = warm
    return run_ipopt(problem, theta0, WARM_START_OPTIONS)


def test_only_the_actuator_rows_far_inside_their_bounds_are_left_out(warm):
    problem, theta0 = warm
    rows = problem.kernel.rows
    left_out = rows_far_from_bounds(problem, theta0)
    assert left_out
    names = {rows[i] for i in left_out}
    # the ground rows and the joints' own coordinates (bounds on variables) always stay
    assert not names & {"foot_z", "foot_z_accel", "q_hip", "q_knee", "qd_hip", "qd_knee"}
    values = problem.outputs(theta0)["c"]
    lower, upper = problem.constraint_bounds
    for i in left_out:  # each is inside both bounds at every sample by a tenth of their width
        width = upper[i] - lower[i]
        assert np.all(values[i] - lower[i] >= 0.1 * width)
        assert np.all(upper[i] - values[i] >= 0.1 * width)
    # a larger margin leaves out fewer rows, never others
    assert set(rows_far_from_bounds(problem, theta0, 0.3)) <= set(left_out)
    assert rows_far_from_bounds(problem, theta0, 0.5) == ()


def test_a_screened_answer_is_an_answer_of_the_whole_problem(warm, whole):
    problem, theta0 = warm
    screened = run_ipopt(problem, theta0, WARM_START_OPTIONS, screen=True)
    assert screened.success and whole.success
    left_out = [
        problem.kernel.rows.index(n) for n in screened.details.stats["rows_left_out"].split(",")
    ]
    assert left_out
    # every row left out is strictly inside its bounds at the answer: their multipliers are zero,
    # so Ipopt's KKT point of the smaller NLP is one of the whole problem
    values = problem.outputs(screened.theta)["c"]
    lower, upper = problem.constraint_bounds
    for i in left_out:
        assert np.all(values[i] > lower[i]) and np.all(values[i] < upper[i])
    assert strictly_inside(problem, screened.theta, tuple(left_out))
    # here the same local optimum as with every row (to Ipopt's tolerance of 1e-8 relative)
    assert screened.swing_energy_j == pytest.approx(whole.swing_energy_j, rel=1e-8)


def test_an_answer_that_crosses_a_row_left_out_is_solved_again_with_every_row(
    warm, whole, monkeypatch
):
    """Leaving out the ground lets the foot dip below it: that answer is discarded."""
    problem, theta0 = warm
    ground = problem.kernel.rows.index("foot_z")
    without_ground = solve_module._run_ipopt(
        problem, theta0, WARM_START_OPTIONS, (ground,), time.perf_counter()
    )
    assert not without_ground.success  # the exact check with every row refuses it
    assert not strictly_inside(problem, without_ground.theta, (ground,))
    monkeypatch.setattr(solve_module, "rows_far_from_bounds", lambda p, t: (ground,))
    again = run_ipopt(problem, theta0, WARM_START_OPTIONS, screen=True)
    assert again.success
    assert again.details.stats["rows_left_out"] == ""
    np.testing.assert_array_equal(again.theta, whole.theta)  # the solve with every row, bitwise
