"""A sagittal plan written as a 3-D plan (:mod:`scalf_opt.sim.sagittal_cycle`).

The 3-D referee runs what the sagittal model planned only if the conversion keeps it: the legs'
joint motion, the level trunk at the height that puts the stance feet on the ground, and stance
forces that carry the robot as far as two diagonal feet can. What they cannot carry is the moment
about the line joining them, and only that: the wrench Pinocchio's ``rnea`` leaves on the trunk
must be a pure moment along the diagonal.
"""

import functools

import numpy as np
import pinocchio as pin
import pytest

from scalf_opt.api.gaits import read_gait
from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.robots.loading import load_robot
from scalf_opt.sim.plan import REFERENCE_SWINGS, TrotPlan
from scalf_opt.sim.sagittal_cycle import cycle_nodes, sagittal_cycle_plan
from scalf_opt.types import LEG_NAMES


@functools.cache
def _converted(name):
    robot = load_robot(name)
    pipeline = EnergyPipeline(robot, read_gait(robot=robot), "paper")
    physics = WholeBodyPhysics.of(robot)
    return robot, pipeline, physics, sagittal_cycle_plan(pipeline, REFERENCE_SWINGS, physics)


@pytest.fixture(params=["scalf", "go1"])
def converted(request):
    return _converted(request.param)


def test_the_nodes_hold_a_whole_stance_at_the_rate_or_more():
    assert cycle_nodes(0.5, 0.5) == 200
    n = cycle_nodes(0.3527, 0.6)
    assert n >= 0.3527 * 400 and (0.6 * n) == pytest.approx(round(0.6 * n), abs=1e-9)


def test_the_legs_move_as_planned_and_the_trunk_rides_level(converted):
    robot, pipeline, physics, plan = converted
    t = plan.schedule.times_s
    sagittal = TrotPlan.build(pipeline, REFERENCE_SWINGS, 4 / plan.schedule.step_s)
    moved = set()
    for leg in LEG_NAMES:
        q = sagittal.sample(leg, t, ("q",))["q"]
        for row, joint in enumerate(robot.leg(leg).joint_names):
            j = physics.joint_names.index(joint)
            np.testing.assert_allclose(plan.x[6 + j], q[row], rtol=0, atol=1e-12)
            moved.add(j)
    still = [6 + j for j in range(physics.n_joints) if j not in moved]
    np.testing.assert_array_equal(plan.x[still], 0.0)  # the abduction joints at zero
    np.testing.assert_array_equal(plan.x[3:6], 0.0)  # level, heading straight
    np.testing.assert_allclose(plan.x[0], plan.speed_m_s * t, rtol=0, atol=1e-15)
    # the stance feet on the ground at every stance node, and still between nodes
    feet = plan.node_outputs("paper")["feet_pos"].reshape(3, -1, 4)
    for i in range(4):
        np.testing.assert_allclose(feet[2, plan.schedule.stance[i], i], 0.0, atol=1e-9)
    assert plan.check("paper").stance_slip_m < 1e-4


def test_the_forces_carry_all_but_the_moment_about_the_diagonal(converted):
    _, _, physics, plan = converted
    model = physics.model
    data = model.createData()
    q, v, a = plan.pinocchio_states
    weight = physics.weight_n
    frames = [model.getFrameId(f) for f in physics.feet]
    two_feet = 0
    for k in range(plan.schedule.intervals):
        on = np.flatnonzero(plan.schedule.stance[:, k])
        pin.framesForwardKinematics(model, data, q[:, k])
        fext = [pin.Force.Zero() for _ in range(model.njoints)]
        for i, fid in enumerate(frames):
            frame = model.frames[fid]
            local = data.oMi[frame.parentJoint].rotation.T @ plan.forces_n[3 * i : 3 * i + 3, k]
            fext[frame.parentJoint] += pin.Force(
                local, np.cross(frame.placement.translation, local)
            )
        left = pin.rnea(model, data, q[:, k], v[:, k], a[:, k], fext)[:6]
        # the trunk is level: its axes are the world's
        assert np.abs(left[:3]).max() < 1e-9 * weight
        if on.size == 2:
            two_feet += 1
            line = data.oMf[frames[on[1]]].translation - data.oMf[frames[on[0]]].translation
            moment = left[3:]
            assert np.linalg.norm(np.cross(moment, line)) < 1e-9 * weight * np.linalg.norm(line)
        else:
            assert np.abs(left[3:]).max() < 1e-9 * weight
    assert two_feet > plan.schedule.intervals / 2


def test_on_scalf_the_3d_model_of_the_plan_costs_what_the_sagittal_model_says():
    """Two implementations of the same loads: the sagittal pipeline's minimum-norm distribution
    of the whole robot's inverse dynamics, and Pinocchio's floating-base wrench shared here.
    SCalf's abduction joints have ideal drives, so with them at rest the 3-D model charges what
    the sagittal one does; the plan is read at ten times 400 Hz against the pipeline's rate, and
    its joints are a spline through the samples (measured: 0.5 % apart per leg). Go1's
    abduction motors pay copper loss for the torque they hold, which the sagittal model has no
    joint for."""
    from scalf_opt.energy.swings import planned_cycle

    _, pipeline, physics, plan = _converted("scalf")
    sagittal = planned_cycle(pipeline, REFERENCE_SWINGS)
    energy = plan.check("paper").energy.joint_energy_j
    legs = np.array(physics.joint_legs)
    for i, leg in enumerate(LEG_NAMES):
        assert energy[legs == i].sum() == pytest.approx(sagittal.legs[leg].energy_j, rel=0.01)
