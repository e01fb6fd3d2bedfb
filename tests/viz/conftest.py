"""Shared fixtures of the view and figure tests: coarse gaits keep them fast."""

from dataclasses import replace

import pytest

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.optimize.problem import SwingProblem
from scalf_opt.optimize.solve import run_ipopt
from scalf_opt.types import FIRST_PAIR
from scalf_opt.viz.trajectories import REFERENCE_LABEL, Trajectory

COARSE_RATE_HZ = 40.0
"""10 intervals per 0.25 s phase: every figure and scene is built, at a fraction of the cost."""


def coarse_pipeline(robot):
    gait = replace(default_gait_for(robot), sample_rate_hz=COARSE_RATE_HZ)
    return EnergyPipeline(robot, gait)


def reference_trajectory(pipeline):
    return Trajectory(REFERENCE_LABEL, pipeline.robot_cycle(make_family("reference")))


def optimized_trajectory(pipeline, family_name):
    """A family's Ipopt optimum at the pipeline's own (coarse) rate: something to draw.

    The figures only draw what they are given; converged optima come from the one driver,
    which the tests of ``view``, ``figures`` and the same-numbers test exercise.
    """
    family = make_family(family_name)
    thetas = {leg: run_ipopt(SwingProblem(pipeline, leg, family)).theta for leg in FIRST_PAIR}
    return Trajectory(f"optimum ({family_name})", pipeline.robot_cycle(family, thetas))


@pytest.fixture(scope="session")
def scalf_shown(scalf):
    """SCalf's reference and the paper family's optimum (Ipopt), on the coarse gait."""
    pipeline = coarse_pipeline(scalf)
    return pipeline, [
        reference_trajectory(pipeline),
        optimized_trajectory(pipeline, "paper"),
    ]


def reference_only(pipeline):
    return [Trajectory("reference", pipeline.robot_cycle(make_family("reference")))]
