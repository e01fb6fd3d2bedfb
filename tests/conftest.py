"""Shared fixtures: robots are parsed once per session."""

import pytest
from hypothesis import settings

from scalf_opt.robots.loading import load_robot

# the same examples on every run and machine: a failure reproduces, CI never flickers
settings.register_profile("deterministic", derandomize=True, deadline=None)
settings.load_profile("deterministic")


@pytest.fixture(scope="session")
def scalf():
    return load_robot("scalf")


@pytest.fixture(scope="session")
def hyq():
    return load_robot("hyq")


@pytest.fixture(scope="session")
def solo12():
    return load_robot("solo12")


@pytest.fixture(scope="session")
def optimum(tmp_path_factory):
    """SCalf's default optimum as `scalf-opt optimize --out DIR` saves it (the DIR)."""
    from scalf_opt.cli import main

    out = tmp_path_factory.mktemp("optimum")
    assert main(["optimize", "--out", str(out), "-q"]) == 0
    return out


@pytest.fixture(scope="session")
def cheapest_trot(scalf):
    """SCalf's cheapest trot at the paper's speed (1.0 m/s), ``paper`` family, trunk-only loads
    (docs/gaits.md's; ~25 s: whole-body loads alternate the coupled legs, ten times longer)."""
    from scalf_opt.energy.pipeline import EnergyPipeline
    from scalf_opt.locomotion.gait import Gait
    from scalf_opt.locomotion.swing.registry import make_family
    from scalf_opt.optimize.gait_search import GaitGoal, optimize_gait

    return optimize_gait(
        EnergyPipeline(scalf, Gait(), loads="trunk"), GaitGoal(1.0, make_family("paper"))
    )


@pytest.fixture(scope="session")
def go1_cycle():
    """Go1's 3-D trot cycle solved on 10 nodes: ``(problem, solution)`` (about a minute).

    Shared by the modules of the ``whole_body_cycle`` xdist group, which run on one worker.
    """
    from scalf_opt.energy.whole_body import WholeBodyPhysics
    from scalf_opt.locomotion.contact_schedule import trot_schedule
    from scalf_opt.locomotion.scaling import default_gait_for
    from scalf_opt.optimize.whole_body_nlp import CycleProblem, solve_cycle
    from scalf_opt.robots.loading import load_robot

    robot = load_robot("go1")
    gait = default_gait_for(robot)
    schedule = trot_schedule(gait.period_s, 0.5, 25.0)  # 10 nodes
    problem = CycleProblem(
        WholeBodyPhysics.of(robot),
        schedule,
        gait.speed_m_s,
        gait.stance_height_m,
        gait.clearance_m,
    )
    return problem, solve_cycle(problem)
