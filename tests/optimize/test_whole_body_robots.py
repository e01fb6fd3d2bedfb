"""Every catalog robot's optimized 3-D cycle against Pinocchio's own free-flyer model.

Go1's plan is checked in ``test_whole_body_cycle.py`` (with its export); here the other five
robots' plans, each solved on the coarsest grid the driver starts from (8 nodes at duty 0.5),
and SCalf's also on the next grid from that optimum, the solve that crept for thousands of
iterations before the objective was scaled for Ipopt
(:data:`~scalf_opt.optimize.whole_body_nlp.OBJECTIVE_SCALING`).
"""

import casadi as ca
import numpy as np
import pytest

from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.locomotion.contact_schedule import trot_schedule
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.optimize.whole_body_driver import resampled
from scalf_opt.optimize.whole_body_nlp import (
    CycleProblem,
    build_cycle_nlp,
    kinematic_start,
    solve_cycle,
)
from scalf_opt.robots.loading import load_robot
from tests.optimize.whole_body_checks import assert_contacts_hold, assert_pinocchio_agrees

ROBOTS = ("scalf", "a1", "hyq", "anymal_c", "solo12")

CREPT_MAX_ITER = 600
"""SCalf's 12-node solve converges in about 200 iterations; unscaled it had not after 1,500."""


def problem_on(robot_name: str, nodes: int) -> CycleProblem:
    robot = load_robot(robot_name)
    gait = default_gait_for(robot)
    schedule = trot_schedule(gait.period_s, 0.5, nodes / gait.period_s)
    assert schedule.intervals == nodes
    return CycleProblem(
        WholeBodyPhysics.of(robot),
        schedule,
        gait.speed_m_s,
        gait.stance_height_m,
        gait.clearance_m,
    )


@pytest.mark.slow
@pytest.mark.parametrize("robot_name", ROBOTS)
def test_each_robot_s_optimum_is_pinocchio_s_dynamics_inside_the_cones(robot_name):
    problem = problem_on(robot_name, 8)
    solution = solve_cycle(problem)
    assert solution.success, solution.status
    if robot_name == "scalf":
        finer = problem_on(robot_name, 12)
        solution = solve_cycle(finer, resampled(solution.plan, finer), {"max_iter": CREPT_MAX_ITER})
        assert solution.success, solution.status
        problem = finer
    start = solution.start.evaluate("paper").total_j
    assert solution.plan.evaluate("paper").total_j < start
    assert_pinocchio_agrees(problem, solution.plan)
    assert_contacts_hold(problem, solution.plan)


def test_every_constraint_row_moves_with_a_free_variable():
    """No row is a constant of the variables Ipopt may move: a row fixed at its bound by the
    variables' own bounds (a cone row where the force is held at zero) is degenerate."""
    problem = problem_on("go1", 8)
    nlp = build_cycle_nlp(problem, kinematic_start(problem))
    pattern = ca.jacobian_sparsity(nlp.constraints, nlp.variables)
    rows, cols = (np.array(a) for a in pattern.get_triplet())
    free = nlp.lbw != nlp.ubw
    moved = np.zeros(nlp.constraints.shape[0], dtype=bool)
    moved[rows[free[cols]]] = True
    names = np.array(nlp.row_names)
    assert moved.all(), sorted(set(names[~moved]))
