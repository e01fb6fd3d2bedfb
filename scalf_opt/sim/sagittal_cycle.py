"""A sagittal plan as a 3-D plan, so that the 3-D referee can run it with the trunk free.

The sagittal model plans a trot whose trunk rides level at a constant height and speed, whose
legs move in their sagittal planes (the abduction joints held at zero) and whose stance feet
share the whole robot's loads by the minimum-norm distribution. Written as a
:class:`~scalf_opt.energy.whole_body_plan.WholeBodyPlan` on ``N`` nodes of the gait cycle:

* the coordinates: the trunk at ``x = v t``, ``y = 0``, level, at the height that puts the stance
  feet on the ground; each leg's hip pitch and knee as the sagittal pipeline plans them, sampled
  at the nodes and joined by the periodic C2 spline through them
  (:func:`~scalf_opt.locomotion.periodic_spline.fit`); every other joint at zero;
* the contact forces: at each node, the minimum-norm forces of the feet on the ground (both pairs
  at the instant one lands and the other lifts off) that carry the floating base's wrench, which
  Pinocchio's ``rnea`` of that motion gives. Two diagonal feet carry every wrench but a moment
  along the line joining them: the plan leaves exactly that moment unbalanced (its ``check``
  reports it), as the sagittal model does, and in the 3-D referee it acts on the trunk, which the
  sagittal referee's planar trunk never lets it do.

Its energy (the 3-D model's drives and accounting on that motion and those forces) is what the
3-D referee's verdict compares with; the sagittal model's own energy is reported beside it.
"""

from __future__ import annotations

import math
from collections.abc import Mapping

import numpy as np
import pinocchio as pin

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.energy.whole_body_plan import WholeBodyPlan
from scalf_opt.errors import GaitError
from scalf_opt.locomotion.contact_schedule import TrotSchedule
from scalf_opt.locomotion.periodic_spline import fit
from scalf_opt.sim.plan import SwingChoice, TrotPlan
from scalf_opt.types import LEG_NAMES

NODE_RATE_HZ = 400.0
"""The nodes' least rate [Hz]: the sagittal plan's swings are smooth, its forces jump at every
touch-down; 400 Hz puts each jump within 2.5 ms."""


def cycle_nodes(period_s: float, duty_cycle: float, rate_hz: float = NODE_RATE_HZ) -> int:
    """The fewest nodes at ``rate_hz`` or more on which the stance is a whole number of nodes.

    Raises:
        GaitError: No such count within a thousand more nodes (a duty factor that is no
            fraction of small denominator).
    """
    first = math.ceil(period_s * rate_hz)
    for n in range(first, first + 1000):
        if abs(duty_cycle * n - round(duty_cycle * n)) < 1e-9:
            return n
    raise GaitError(
        f"duty factor {duty_cycle:g}: no grid near {rate_hz:g} Hz holds a whole stance",
        field="duty_cycle",
    )


def sagittal_cycle_plan(
    pipeline: EnergyPipeline,
    swings: Mapping[str, SwingChoice],
    physics: WholeBodyPhysics,
    nodes: int | None = None,
) -> WholeBodyPlan:
    """The sagittal plan of ``pipeline`` and ``swings`` as a 3-D plan (module docstring).

    Args:
        pipeline: The sagittal energy model (robot, gait, loads).
        swings: Every leg's swing.
        physics: The 3-D model of the same robot.
        nodes: Nodes per cycle (default: :func:`cycle_nodes`).
    """
    gait, robot = pipeline.gait, pipeline.robot
    period = gait.period_s
    n = nodes or cycle_nodes(period, gait.duty_cycle)
    schedule = TrotSchedule(period, gait.duty_cycle, n)
    sagittal = TrotPlan.build(pipeline, swings, 4 * n / period)
    t = schedule.times_s
    x = np.zeros((physics.nx, n))
    for leg in LEG_NAMES:
        angles = sagittal.sample(leg, t, ("q",))["q"]
        for row, joint in enumerate(robot.leg(leg).joint_names):
            x[6 + physics.joint_names.index(joint)] = angles[row]
    speed = gait.speed_m_s
    x[0] = speed * t
    feet = np.stack([np.array(physics.feet_function(x[:, k])) for k in range(n)])  # (n, 3, 4)
    x[2] = -float(np.mean(feet[:, 2, :][schedule.stance.T]))
    shift = physics.stride_shift(speed * period)
    xd, xdd = fit(x, schedule.step_s, shift)
    forces = _minimum_norm_forces(physics, schedule, x, xd, xdd)
    holds = np.array(
        [feet[schedule.touchdown_node(leg), :2, i] for i, leg in enumerate(LEG_NAMES)]
    ).T
    return WholeBodyPlan(physics, schedule, speed, x, xd, xdd, forces, holds)


def _minimum_norm_forces(
    physics: WholeBodyPhysics,
    schedule: TrotSchedule,
    x: np.ndarray,
    xd: np.ndarray,
    xdd: np.ndarray,
) -> np.ndarray:
    """The stance feet's minimum-norm forces (12, N) [N] carrying the base's wrench at each node."""
    model = physics.model
    data = model.createData()
    n = schedule.intervals
    qs, vs, accelerations = (
        np.array(m) for m in physics.pinocchio_state_function.map(n)(x, xd, xdd)
    )
    frames = [model.getFrameId(foot) for foot in physics.feet]
    forces = np.zeros((3 * len(frames), n))
    for k in range(n):
        on = np.flatnonzero(schedule.stance[:, k])
        if on.size == 0:
            continue
        q = qs[:, k]
        wrench = pin.rnea(model, data, q, vs[:, k], accelerations[:, k])[:6]
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)
        carry = np.hstack(
            [
                pin.getFrameJacobian(model, data, frames[i], pin.LOCAL_WORLD_ALIGNED)[:3, :6].T
                for i in on
            ]
        )
        if on.size == 2:
            # two feet carry every wrench but a moment along the line joining them, and nothing
            # else is missing: that moment is a seventh unknown, left unbalanced (in the trunk's
            # axes, as the wrench), the least norm choosing no force along the line
            line = data.oMf[frames[on[1]]].translation - data.oMf[frames[on[0]]].translation
            axis = data.oMi[1].rotation.T @ line / np.linalg.norm(line)
            carry = np.hstack([carry, np.r_[np.zeros(3), axis][:, None]])
        shares = np.linalg.lstsq(carry, wrench, rcond=None)[0]
        for j, i in enumerate(on):
            forces[3 * i : 3 * i + 3, k] = shares[3 * j : 3 * j + 3]
    return forces
