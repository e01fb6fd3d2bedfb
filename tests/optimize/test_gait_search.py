"""The cheapest trot at a speed: not above the paper's gait, within every limit at ten times its
rate, no cheaper point on a brute-force grid, and a pinned answer says what pins it.

Relative checks only (the cheapest against the paper's gait with optimized swings against the
reference, the search against a grid): the energy model's numbers may change, these orders may
not. The ``paper`` family keeps the search to ~25 s; the orders hold for every family.
"""

import math
from dataclasses import replace

import numpy as np
import pytest

from scalf_opt.energy.peaks import cycle_violations
from scalf_opt.errors import ConfigError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.driver import Settings
from scalf_opt.optimize.free_stance import GaitTrials
from scalf_opt.optimize.gait_search import (
    INITIAL_STEP,
    SEARCH_UNIT,
    GaitBox,
    at_speed,
    check_speed,
    cost_of_transport,
    gait_at,
    limit_name,
    reference_unwalkable,
)
from scalf_opt.optimize.sampling import CHECK_FACTOR, with_rate
from scalf_opt.types import FIRST_PAIR

FAMILY = "paper"


@pytest.fixture(scope="module")
def search(cheapest_trot):
    """SCalf at the paper's speed (1.0 m/s) from the paper's trot (``paper`` family)."""
    return cheapest_trot


def test_the_paper_s_gait_retimed_to_its_own_speed_is_the_paper_s_gait():
    assert at_speed(Gait(), 1.0) == Gait()  # S = v d T = 1.0 * 0.5 * 0.5 = 0.25 m
    fast = at_speed(Gait(), 1.5)
    assert fast.speed_m_s == pytest.approx(1.5, rel=1e-12)
    assert fast.step_length_m == pytest.approx(0.375, rel=1e-12)


def test_a_searched_gait_s_fields_are_the_nearest_floats_to_their_grid_values():
    # 57.5 units times 0.01 is 0.5750000000000001, which gaits.csv printed as the duty
    gait = gait_at(Gait(), 1.0, np.array([55.0, 57.5, 77.5, 2.5, -1.5]))
    assert (gait.period_s, gait.duty_cycle) == (0.55, 0.575)
    assert (gait.stance_height_m, gait.stance_x_offset_front_m) == (0.775, 0.025)
    assert gait.stance_x_offset_hind_m == -0.015
    assert repr(gait.duty_cycle) == "0.575"


def test_the_cheapest_is_not_above_the_paper_s_gait_nor_the_reference(search):
    assert search.success
    cheapest = search.cycle().cost_of_transport
    paper = search.default_cycle()
    assert paper is not None and search.reference is not None
    assert paper.gait.period_s == 0.5 and paper.gait.duty_cycle == 0.5
    assert paper.gait.step_length_m == pytest.approx(0.25, rel=1e-12)
    assert cheapest <= paper.cost_of_transport <= search.reference.cost_of_transport
    # the search's objective is the robot cycle's cost of transport (LF, RH repeat RF, LH)
    assert search.cost_of_transport(search.best) == pytest.approx(cheapest, rel=1e-9)
    assert search.cycle().gait.speed_m_s == pytest.approx(1.0, rel=1e-12)
    assert search.cycle().symmetry_error < 1e-12


def test_the_cheapest_respects_every_limit_at_ten_times_its_rate(search):
    run = search.best.run
    gait = run.pipeline.gait
    fine = run.pipeline.with_gait(with_rate(gait, CHECK_FACTOR * gait.sample_rate_hz))
    cycle = fine.robot_cycle(make_family(FAMILY), run.thetas)
    physics = {leg: fine.physics(leg) for leg in cycle.legs}
    assert cycle_violations(cycle, physics) == []
    # its energy has converged in the sampling (the driver's tolerance, 0.5 %)
    assert cycle.energy_j == pytest.approx(search.cycle().energy_j, rel=5e-3)
    assert reference_unwalkable(fine) is None  # every command can compare it with the reference


def test_no_point_of_a_brute_force_grid_is_cheaper_than_the_grid_s_resolution_explains(
    search, scalf
):
    """Period and duty on a grid around the answer (its stance), swings optimized at each point.

    The answer is a local minimum at the search's last step; a grid point may beat it only by
    what one grid step changes the cost of transport near the answer (the largest change to a
    feasible neighbour one grid step away), plus the sampling's 0.5 %.
    """
    best = search.best.gait
    trials = GaitTrials(
        search.best.run.pipeline.with_gait(best),
        make_family(FAMILY),
        Settings(),
        stance_at_swing_rate=True,
    )
    d_period, d_duty = 0.05, 0.05  # the grid's resolution: 50 ms and 0.05
    periods = best.period_s + d_period * np.arange(-3, 4)
    duties = np.arange(0.5, 0.76, d_duty)
    mass = scalf.total_mass_kg

    def cot(period: float, duty: float) -> float:
        gait = at_speed(replace(best, period_s=float(period), duty_cycle=float(duty)), 1.0)
        if reference_unwalkable(trials.pipeline.with_gait(gait)) is not None:
            return math.inf  # the search refuses these gaits too
        return cost_of_transport(trials.evaluate(gait), mass, 1.0)

    grid = {(p, d): cot(p, d) for p in periods for d in duties}
    feasible = [v for v in grid.values() if math.isfinite(v)]
    assert len(feasible) >= 8  # the grid explores, not only the answer's corner
    answer = cot(best.period_s, best.duty_cycle)
    near = [
        cot(best.period_s + dp, best.duty_cycle + dd)
        for dp, dd in ((d_period, 0), (-d_period, 0), (0, d_duty), (0, -d_duty))
        if best.duty_cycle + dd >= 0.5
    ]
    resolution = max(abs(v - answer) for v in near if math.isfinite(v))
    assert min(feasible) >= answer - resolution - 5e-3 * answer


def test_a_pinned_answer_names_its_limits(search):
    # SCalf's cheapest trot at 1.0 m/s has the least duty cycle: a trot's floor pins it
    assert search.best.gait.duty_cycle == pytest.approx(0.5)
    assert "duty_cycle down" in search.pinned
    assert "a trot's floor" in limit_name(search.pinned["duty_cycle down"])
    for reason in search.pinned.values():
        assert len(limit_name(reason)) <= 80


def test_limit_names_are_short_and_name_the_limit():
    from scalf_opt.energy.pipeline import EnergyPipeline
    from scalf_opt.energy.workspace import check_joint_limits
    from scalf_opt.errors import InfeasibleError
    from scalf_opt.robots.loading import load_robot

    # a joint's range, as the workspace check words it, on Go1 (whose URDF calls LH's knee
    # RL_calf_joint): named by the leg's and the joint's role, as the stance's own bounds are
    kin = EnergyPipeline(load_robot("go1"), Gait()).kinematics("LH")
    q = np.array([[0.0], [10.0]])  # the knee far outside its range
    with pytest.raises(InfeasibleError) as info:
        check_joint_limits(kin, q, "swing")
    joint = str(info.value)
    assert "RL_calf_joint (q_knee)" in joint
    names = {
        f"gait fields stance_height_m = 0.79 are impossible for this robot: {joint}": (
            "LH q_knee: joint range (URDF)"
        ),
        f"the reference swing of LH cannot walk it: gait fields ... {joint}": (
            "LH q_knee: joint range under the reference swing"
        ),
        "stance of LH: q_knee beyond its joint range (URDF)": "LH q_knee: joint range (URDF)",
        "stance of LH: tau_knee beyond its URDF effort limit": "LH tau_knee: URDF effort limit",
        "leg RF: foot target (x=0.1 m, z=0.9 m) is 0.91 m from the hip, outside the reach "
        "[0.1, 0.8] m": "RF reach",
        "duty_cycle below the search box's 0.5, a trot's floor": (
            "duty_cycle below the search box's 0.5, a trot's floor"
        ),
    }
    for reason, name in names.items():
        assert limit_name(reason) == name


def test_the_box_keeps_a_trot_a_trot():
    box = GaitBox.around(Gait())
    assert (box.period_min_s, box.period_max_s, box.duty_min) == (0.2, 1.25, 0.5)
    assert box.outside(Gait()) is None
    assert "a trot's floor" in box.outside(Gait(), duty=0.49)
    assert "period_s above" in box.outside(replace(Gait(), period_s=1.3))
    with pytest.raises(ConfigError, match="flight phase"):
        GaitBox(0.2, 1.0, duty_min=0.4)
    with pytest.raises(ConfigError, match="speed"):
        check_speed(0.0)
    with pytest.raises(ConfigError, match="speed"):
        check_speed(float("nan"))
    # the first steps are 50 ms, 0.05 and 2 cm
    assert np.allclose(np.asarray(INITIAL_STEP) * SEARCH_UNIT, (0.05, 0.05, 0.02, 0.02, 0.02))


def test_the_robot_s_energy_is_twice_the_diagonal_pair_s(search):
    pair = sum(search.cycle().legs[leg].energy_j for leg in FIRST_PAIR)
    assert 2 * pair == pytest.approx(search.cycle().energy_j, rel=1e-12)
    assert 2 * search.best.total_j == pytest.approx(search.cycle().energy_j, rel=1e-9)
