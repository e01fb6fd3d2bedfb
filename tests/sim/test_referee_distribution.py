"""The simulation referee's planned stance forces are the sagittal distribution of the whole-body
wrench (``--loads whole-body-sagittal``), not the 3-D one (``whole-body``).

The referee's trunk moves in its sagittal plane only: its plan (:func:`scalf_opt.sim.inverse
.plan_torques`) takes the trunk's rows of MuJoCo's inverse dynamics and shares them over the
stance feet by the minimum norm in x, z and pitch. scalf-opt computes the same wrench from
Pinocchio and its own distribution maps. On ANYmal C the two distributions differ most (the
moment about the diagonal is the largest share of its stance loads), so the check tells them
apart: the plan equals the sagittal model and not the 3-D one.
"""

import numpy as np
import pytest

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.locomotion.scaling import default_gait_for
from scalf_opt.locomotion.trot import stance_start_s
from scalf_opt.robots.loading import load_robot
from scalf_opt.sim.inverse import plan_torques
from scalf_opt.sim.mujoco_model import build_sim_model
from scalf_opt.sim.plan import REFERENCE_SWINGS, TrotPlan
from scalf_opt.sim.settings import SimSettings

# [N] on stance forces of ~250 N: two inverse-dynamics codes (MuJoCo, Pinocchio) on one model,
# the plan's grid the model's, so no interpolation enters; round-off alone is ~1e-9
TOL_N = 1e-6


@pytest.mark.parametrize("leg", ["RF", "LH"])
def test_the_referees_plan_shares_the_wrench_as_the_sagittal_model(leg):
    robot = load_robot("anymal_c")
    pipeline = EnergyPipeline(robot, default_gait_for(robot), loads="whole-body-sagittal")
    settings, _ = SimSettings().for_leg_length(robot.leg_length_m)
    sim = build_sim_model(robot, settings)
    plan = TrotPlan.build(pipeline, REFERENCE_SWINGS, pipeline.gait.sample_rate_hz)
    times = stance_start_s(pipeline.gait, leg) + pipeline.stance_times_s[:-1]  # not lift-off
    _, grf = plan_torques(sim, plan, times, pipeline.gait.stance_height_m)
    n = times.size
    sagittal = pipeline.stance_forces(leg).sagittal_n[:, :n]
    np.testing.assert_allclose(grf[leg], sagittal, rtol=0, atol=TOL_N)
    three_d = pipeline.with_loads("whole-body").stance_forces(leg).sagittal_n[:, :n]
    assert np.abs(grf[leg] - three_d).max() > 50.0  # the 3-D distribution is another one
