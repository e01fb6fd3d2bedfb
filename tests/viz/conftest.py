"""Shared fixtures of the view and figure tests: coarse gaits keep them fast."""

from dataclasses import replace

import pytest

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.locomotion.swing.registry import make_family
from scalf_opt.viz.trajectories import Trajectory, optimized_trajectory, reference_trajectory

COARSE_RATE_HZ = 40.0
"""10 intervals per 0.25 s phase: every figure and scene is built, at a fraction of the cost."""


def coarse_pipeline(robot):
    gait = replace(default_gait_for(robot), sample_rate_hz=COARSE_RATE_HZ)
    return EnergyPipeline(robot, gait)


@pytest.fixture(scope="session")
def scalf_shown(scalf):
    """SCalf's reference and the paper family's optimum (Ipopt), on the coarse gait."""
    pipeline = coarse_pipeline(scalf)
    return pipeline, [
        reference_trajectory(pipeline),
        optimized_trajectory(pipeline, "paper", "ipopt"),
    ]


def reference_only(pipeline):
    return [Trajectory("reference", pipeline.robot_cycle(make_family("reference")))]
