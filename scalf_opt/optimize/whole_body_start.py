"""A kinematic reference trot in 3-D: the trunk level at constant speed, the feet on a simple path.

The trunk rides level at the gait's height (its pitching hips ``stance_height_m`` above the
ground) at the average speed; each foot stands under its hip at mid-stance and swings to its next
foothold on a minimum-jerk path in x with a lift of ``1.1 H`` (``64 s^3 (1 - s)^3``). The joints
follow by Pinocchio's inverse kinematics (damped Gauss-Newton on the four feet at once, from the
robot's reference posture); the rates and second derivatives are the periodic spline's through
those nodes; each stance foot carries an equal share of the weight (none at touch-down and
lift-off). It is a start for an optimizer, not a balanced motion: its forces do not carry the
robot's accelerations (:meth:`~scalf_opt.energy.whole_body_plan.WholeBodyPlan.check` says by how
much).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.energy.whole_body_plan import WholeBodyPlan
from scalf_opt.locomotion.contact_schedule import TrotSchedule
from scalf_opt.locomotion.periodic_spline import fit
from scalf_opt.types import LEG_NAMES

START_LIFT_SHARE = 1.1
"""The start's swing apex as a share of the clearance H (a little above the bound)."""

IK_ITERATIONS = 50
IK_DAMPING = 1e-6


def reference_joints(physics: WholeBodyPhysics) -> np.ndarray:
    """The joints' start posture [rad].

    Each leg's reference hip pitch and knee, the others at zero (clipped into their ranges).
    """
    model = physics.model
    q = np.zeros(physics.n_joints)
    for leg in LEG_NAMES:
        view = physics.robot.leg(leg)
        for name, value in zip(view.joint_names, view.reference_posture_rad, strict=True):
            q[physics.joint_names.index(name)] = value
    lower, upper = model.lowerPositionLimit[7:], model.upperPositionLimit[7:]
    return np.clip(q, lower, upper)


def hip_height_offset_m(physics: WholeBodyPhysics) -> float:
    """The pitching hips' mean height below the trunk's origin [m] (positive when below)."""
    model = physics.model
    data = model.createData()
    q = pin.neutral(model)
    pin.forwardKinematics(model, data, q)
    heights = [
        data.oMi[model.getJointId(physics.robot.leg(leg).joint_names[0])].translation[2]
        for leg in LEG_NAMES
    ]
    return -float(np.mean(heights))


def starting_plan(
    physics: WholeBodyPhysics,
    schedule: TrotSchedule,
    speed_m_s: float,
    stance_height_m: float,
    clearance_m: float,
) -> WholeBodyPlan:
    """The start described in the module docstring."""
    model = physics.model
    data = model.createData()
    n, period = schedule.intervals, schedule.period_s
    stride = speed_m_s * period
    times = schedule.times_s
    base_z = stance_height_m + hip_height_offset_m(physics)
    joints = reference_joints(physics)
    q = np.concatenate([[0.0, 0.0, base_z, 0.0, 0.0, 0.0, 1.0], joints])
    pin.framesForwardKinematics(model, data, q)
    fids = [model.getFrameId(f) for f in physics.feet]
    hips = [model.getJointId(physics.robot.leg(leg).joint_names[0]) for leg in LEG_NAMES]
    footholds = np.zeros((2, len(LEG_NAMES)))
    duty_s = schedule.duty_cycle * period
    targets = np.zeros((3, len(LEG_NAMES), n))
    for i, leg in enumerate(LEG_NAMES):
        touchdown = schedule.touchdown_node(leg) * schedule.step_s
        footholds[0, i] = data.oMi[hips[i]].translation[0] + speed_m_s * (touchdown + duty_s / 2)
        footholds[1, i] = data.oMf[fids[i]].translation[1]
        for k, t in enumerate(times):
            if schedule.stance[i, k]:
                x = footholds[0, i] - stride * schedule.previous_stance[i, k]
                targets[:, i, k] = (x, footholds[1, i], 0.0)
                continue
            # the swing that ends at the next touch-down, on this cycle's foothold or the next's
            ahead = t >= touchdown
            landing = footholds[0, i] + (stride if ahead else 0.0)
            s = 1 - (touchdown + (period if ahead else 0.0) - t) / (period - duty_s)
            # minimum-jerk in x and a bump in z: at rest, unaccelerated, at both ends
            x = landing - stride + stride * s**3 * (10 - 15 * s + 6 * s**2)
            z = START_LIFT_SHARE * clearance_m * 64 * s**3 * (1 - s) ** 3
            targets[:, i, k] = (x, footholds[1, i], z)
    x_nodes = np.zeros((physics.nx, n))
    for k, t in enumerate(times):
        q[0] = speed_m_s * t
        joints = _inverse_kinematics(physics, data, q, fids, targets[:, :, k])
        q[7:] = joints
        x_nodes[:, k] = np.concatenate([[speed_m_s * t, 0.0, base_z, 0.0, 0.0, 0.0], joints])
    xd, xdd = fit(x_nodes, schedule.step_s, physics.stride_shift(stride))
    return WholeBodyPlan(
        physics, schedule, speed_m_s, x_nodes, xd, xdd, _start_forces(physics, schedule), footholds
    )


def _inverse_kinematics(
    physics: WholeBodyPhysics,
    data: pin.Data,
    q: np.ndarray,
    fids: list[int],
    targets: np.ndarray,
) -> np.ndarray:
    """Joint angles that put the feet at ``targets`` (3, 4) with the trunk where ``q`` has it."""
    model = physics.model
    q = q.copy()
    lower, upper = model.lowerPositionLimit[7:], model.upperPositionLimit[7:]
    for _ in range(IK_ITERATIONS):
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)
        error = np.concatenate(
            [targets[:, i] - data.oMf[fid].translation for i, fid in enumerate(fids)]
        )
        if np.abs(error).max() < 1e-10:
            break
        jac = np.vstack(
            [
                pin.getFrameJacobian(model, data, fid, pin.LOCAL_WORLD_ALIGNED)[:3, 6:]
                for fid in fids
            ]
        )
        step = jac.T @ np.linalg.solve(jac @ jac.T + IK_DAMPING * np.eye(jac.shape[0]), error)
        q[7:] = np.clip(q[7:] + step, lower, upper)
    return q[7:].copy()


def _start_forces(physics: WholeBodyPhysics, schedule: TrotSchedule) -> np.ndarray:
    """Each stance foot's equal share of the weight (12, N) [N].

    Vertical, and zero at touch-down and lift-off.
    """
    inner = schedule.loaded
    forces = np.zeros((3 * len(LEG_NAMES), schedule.intervals))
    counts = np.maximum(inner.sum(axis=0), 1)
    for i in range(len(LEG_NAMES)):
        forces[3 * i + 2] = np.where(inner[i], physics.weight_n / counts, 0.0)
    return forces
