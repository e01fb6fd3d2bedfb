"""The 3-D cycle's driver: which grids it solves on (Ipopt replaced by a stand-in that returns
its start as converged, so only the driver's choice of grids is under test)."""

from dataclasses import replace

import pytest

from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.locomotion.contact_schedule import trot_schedule
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.optimize import whole_body_driver
from scalf_opt.optimize.whole_body_driver import CycleResult, optimize_cycle
from scalf_opt.optimize.whole_body_nlp import CycleProblem, CycleSolution, kinematic_start
from scalf_opt.robots.loading import load_robot

RATE_HZ = 25.0


@pytest.fixture(scope="module")
def problem():
    robot = load_robot("go1")
    gait = default_gait_for(robot)
    return CycleProblem(
        WholeBodyPhysics.of(robot),
        trot_schedule(gait.period_s, 0.5, RATE_HZ),
        gait.speed_m_s,
        gait.stance_height_m,
        gait.clearance_m,
    )


def _grids(problem, monkeypatch, start, rule_holds):
    """The node counts the driver solves on, every solve 'converging' at its start."""

    def stand_in(step_problem, first=None):
        plan = kinematic_start(step_problem) if first is None else first
        return CycleSolution(plan, plan, True, "Solve_Succeeded", 0, 0.0)

    monkeypatch.setattr(whole_body_driver, "solve_cycle", stand_in)
    monkeypatch.setattr(whole_body_driver, "RATE_TOLERANCE", 1.0 if rule_holds else 0.0)
    result: CycleResult = optimize_cycle(problem, RATE_HZ, start=start)
    return [step.nodes for step in result.steps]


def _nodes(problem, share):
    """The node count of the problem's trot at ``share`` times the asked rate."""
    return trot_schedule(problem.schedule.period_s, 0.5, share * RATE_HZ).intervals


def test_a_cold_start_refines_from_a_coarse_grid_to_four_times_the_rate(problem, monkeypatch):
    asked = _nodes(problem, 1)
    grids = _grids(problem, monkeypatch, None, rule_holds=False)
    assert grids[0] < asked and grids == sorted(grids)
    assert grids[-2:] == [_nodes(problem, 2), _nodes(problem, 4)]  # two extra doublings at most
    assert _grids(problem, monkeypatch, None, rule_holds=True)[-1] == asked


def test_a_warm_start_keeps_its_grid_up_to_twice_the_rate(problem, monkeypatch):
    """A start on its own grid is solved there; one refined to four times the asked rate is
    solved on twice the rate first, and never beyond the cold path's finest grid."""
    own = kinematic_start(problem)
    assert _grids(problem, monkeypatch, own, rule_holds=True) == [_nodes(problem, 1)]
    fine_schedule = trot_schedule(problem.schedule.period_s, 0.5, 4 * RATE_HZ)
    fine = kinematic_start(replace(problem, schedule=fine_schedule))
    twice = _nodes(problem, 2)
    assert _grids(problem, monkeypatch, fine, rule_holds=True) == [twice]
    assert _grids(problem, monkeypatch, fine, rule_holds=False) == [twice, _nodes(problem, 4)]
