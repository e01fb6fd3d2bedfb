"""The 3-D cycle's driver: which grids it solves on and how densely it reads them (Ipopt replaced
by a stand-in that returns its start as converged, so only the driver's choices are under test)."""

from dataclasses import replace

import pytest

from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.locomotion.contact_schedule import trot_schedule
from scalf_opt.locomotion.periodic_spline import READS_PER_INTERVAL
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
    """The (node count, read points per interval) the driver solves on, every solve
    'converging' at its start."""

    def stand_in(step_problem, first=None):
        plan = kinematic_start(step_problem) if first is None else first
        return CycleSolution(plan, plan, True, "Solve_Succeeded", 0, 0.0)

    monkeypatch.setattr(whole_body_driver, "solve_cycle", stand_in)
    monkeypatch.setattr(whole_body_driver, "RATE_TOLERANCE", 1.0 if rule_holds else 0.0)
    result: CycleResult = optimize_cycle(problem, RATE_HZ, start=start)
    return [(step.nodes, step.reads_per_interval) for step in result.steps]


def _nodes(problem, share):
    """The node count of the problem's trot at ``share`` times the asked rate."""
    return trot_schedule(problem.schedule.period_s, 0.5, share * RATE_HZ).intervals


COARSE, FINE = READS_PER_INTERVAL, whole_body_driver.FINE_READS_PER_INTERVAL


def test_a_cold_start_refines_from_a_coarse_grid_then_doubles_then_reads_denser(
    problem, monkeypatch
):
    """Coarse grids up to the asked rate; while the rule fails, twice the nodes, then that grid
    read at eight points per interval (two refinements at most)."""
    asked, twice = _nodes(problem, 1), _nodes(problem, 2)
    grids = _grids(problem, monkeypatch, None, rule_holds=False)
    assert grids[0][0] < asked and grids == sorted(grids)
    assert all(reads == COARSE for _, reads in grids[:-1])
    assert grids[-3:] == [(asked, COARSE), (twice, COARSE), (twice, FINE)]
    assert _grids(problem, monkeypatch, None, rule_holds=True)[-1] == (asked, COARSE)


def test_a_warm_start_keeps_its_grid_up_to_twice_the_rate(problem, monkeypatch):
    """A start on its own grid is solved there; one refined to four times the asked rate is
    solved on twice the rate first, and never beyond the cold path's finest grid."""
    own = kinematic_start(problem)
    assert _grids(problem, monkeypatch, own, rule_holds=True) == [(_nodes(problem, 1), COARSE)]
    fine_schedule = trot_schedule(problem.schedule.period_s, 0.5, 4 * RATE_HZ)
    fine = kinematic_start(replace(problem, schedule=fine_schedule))
    twice = _nodes(problem, 2)
    assert _grids(problem, monkeypatch, fine, rule_holds=True) == [(twice, COARSE)]
    assert _grids(problem, monkeypatch, fine, rule_holds=False) == [(twice, COARSE), (twice, FINE)]


def test_a_warm_start_read_densely_stays_dense_and_counts_as_a_refinement(problem, monkeypatch):
    """A start that needed the denser reading keeps it; its one refinement left doubles the grid."""
    dense = kinematic_start(problem)
    dense = replace(dense, schedule=replace(dense.schedule, reads_per_interval=FINE))
    period = problem.schedule.period_s
    asked = _nodes(problem, 1)
    twice = trot_schedule(period, 0.5, 2 * asked / period).intervals  # twice the start's rate
    assert _grids(problem, monkeypatch, dense, rule_holds=True) == [(asked, FINE)]
    assert _grids(problem, monkeypatch, dense, rule_holds=False) == [(asked, FINE), (twice, FINE)]


def test_the_grid_change_compares_true_energies_with_the_last_coarser_grid():
    """``grid_change``: the answer's energy at ten times its rate against that of the last solve
    on fewer nodes (a denser reading of the same grid is not a coarser grid); none on one grid."""
    from types import SimpleNamespace

    from scalf_opt.cli.commands.optimize_3d import grid_line
    from scalf_opt.optimize.whole_body_driver import GridStep

    def step(nodes, reads, at_nodes_j, at_10x_j):
        check = SimpleNamespace(energy=SimpleNamespace(total_j=at_10x_j))
        return GridStep(nodes, reads, None, at_nodes_j, check)

    steps = (step(8, 4, 9.0, 12.0), step(16, 4, 9.5, 10.0), step(32, 4, 8.0, 8.2))
    change, nodes = CycleResult(steps).grid_change
    assert nodes == 16 and change == pytest.approx(8.2 / 10.0 - 1, rel=1e-12)
    denser = CycleResult((*steps, step(32, 8, 8.1, 8.12)))
    change, nodes = denser.grid_change
    assert nodes == 16 and change == pytest.approx(8.12 / 10.0 - 1, rel=1e-12)
    assert CycleResult((step(10, 4, 9.0, 9.1), step(10, 8, 9.0, 9.05))).grid_change is None

    line = grid_line({"grid_change": -0.18, "grid_change_from_nodes": 16, "nodes": 32})
    assert "-18.00 % from the 16-node optimum" in line and "cheaper plan" in line
    assert "settled" in grid_line({"grid_change": 0.004, "grid_change_from_nodes": 9, "nodes": 18})
    assert "another local optimum" in grid_line(
        {"grid_change": 0.03, "grid_change_from_nodes": 9, "nodes": 18}
    )
    assert "not measured" in grid_line({"grid_change": None, "nodes": 18})
