"""Step the 3-D referee: a robot free in MuJoCo follows a 3-D plan, and the record of it.

The simulation starts at cycle time 0 in the plan's state (every joint's angle and rate, the
trunk's pose and velocity), raised by the feet's radius so that a foot the plan puts on the
ground touches it with its sphere. Each step (semi-implicit Euler) the controller
(:mod:`scalf_opt.sim.whole_body_control`) sets the joint torques from the state at the step's
start and the plan at that instant (the plan read through Pinocchio's ``rnea`` at every step's
time, :meth:`~scalf_opt.energy.whole_body_plan.WholeBodyPlan.samples`; cycle ``c`` shifted
forward by ``c`` strides). The record holds per step ``k`` the state at its start, the torques
applied over it and the joint rates at its end (``tau_k qd_{k+1} dt`` is exactly the step's joint
work), and per foot the ground's force and where the foot is.

The controller's contact schedule is the plan's, its touch-downs shifted by the settings'
``schedule_shift_s`` (late: a landed leg stays on its swing loop that long; early: a leg switches
to stance that long before the plan says, its foot still in the air), as the sagittal referee's.
The run stops early when the robot falls: the trunk lower than half the plan's lowest height, or
tilted more than :data:`FALL_TILT_RAD` from the plan's orientation; and when MuJoCo reports after
a step that its integration diverged (:mod:`~scalf_opt.sim.divergence`: it has reset the robot
to its initial pose), the record ending before that step.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import mujoco
import numpy as np
import pinocchio as pin

from scalf_opt.energy.whole_body_plan import WholeBodyPlan
from scalf_opt.sim.divergence import clear_divergence, divergence
from scalf_opt.sim.free_model import FreeSimModel, build_free_model
from scalf_opt.sim.settings import SimSettings
from scalf_opt.sim.whole_body_control import (
    WholeBodyController,
    WholeBodyGains,
    whole_body_gains,
)
from scalf_opt.types import LEG_NAMES

FALL_TILT_RAD = math.radians(45.0)
"""A trunk tilted this far from the plan's orientation has fallen."""

_STEP_TOLERANCE = 1e-9
"""A step that starts within this fraction of a step of a cycle's end starts the next cycle."""


def steps_in_cycles(cycles: int, period_s: float, timestep_s: float) -> int:
    """How many steps start within the first ``cycles`` cycles (``k dt < cycles T``).

    The period need not be a whole number of steps: the count is rounded up, so that the steps
    cover the cycles whole (a Go1 trot at T = 0.35276 s and dt = 0.5 ms: two cycles are
    1,411.02 steps, 1,412 steps hold them; 1,411 would leave the second a step short, and it
    would not be measured). Both the run's length (:func:`follow_plan`) and the
    window the metrics measure (:func:`cycles_in_steps`) are counted here, so that a run of
    ``cycles`` cycles holds ``cycles`` cycles whatever the rounding.

    Args:
        cycles: Gait cycles.
        period_s: The gait period [s].
        timestep_s: The simulation's step [s].
    """
    return max(0, math.ceil(cycles * period_s / timestep_s - _STEP_TOLERANCE))


def cycles_in_steps(steps: int, period_s: float, timestep_s: float) -> int:
    """How many whole cycles ``steps`` steps from the start hold (:func:`steps_in_cycles`).

    Args:
        steps: Steps recorded from time 0.
        period_s: The gait period [s].
        timestep_s: The simulation's step [s].
    """
    cycles = int(steps * timestep_s / period_s) + 1  # at most one too many
    while cycles > 0 and steps_in_cycles(cycles, period_s, timestep_s) > steps:
        cycles -= 1
    return cycles


@dataclass(frozen=True)
class WholeBodyRecord:
    """What the 3-D referee recorded, step by step (``n`` steps; cut short by a fall, a divergence).

    Attributes:
        timestep_s: The step [s].
        t_s: Each step's start (n,) [s].
        q, v: The robot's state at each step's start, Pinocchio's convention ((nq, n), (nv, n)).
        qd_next: The joint rates at each step's end (n_joints, n) [rad/s].
        tau_nm: The torques applied over each step (n_joints, n) [N m].
        feedback_nm: Their feedback part, before clipping (n_joints, n) [N m].
        saturated: Which joints asked beyond their effort limit (n_joints, n).
        q_plan: The plan's state at each step (nq, n), raised by the foot radius.
        feet_plan_m: The plan's foot positions (3, 4, n) [m], raised likewise.
        contact_force_n: The ground's force on each foot (3, 4, n) [N], world axes.
        plan_force_n: The plan's force on each foot (3, 4, n) [N], world axes.
        feet_m: Each foot sphere's centre (3, 4, n) [m], world.
        stance: The legs the controller held in stance (4, n).
        plan_stance: The legs the plan puts on the ground (4, n).
        fell_at_s: When the robot fell [s]; ``None`` when it did not.
        diverged_at_s: When the step in which MuJoCo's integration diverged started [s]
            (:mod:`~scalf_opt.sim.divergence`; the record ends before it); ``None`` when it did
            not.
        divergence: Which of MuJoCo's checks failed then, in words; ``None`` when none did.
    """

    timestep_s: float
    t_s: np.ndarray
    q: np.ndarray
    v: np.ndarray
    qd_next: np.ndarray
    tau_nm: np.ndarray
    feedback_nm: np.ndarray
    saturated: np.ndarray
    q_plan: np.ndarray
    feet_plan_m: np.ndarray
    contact_force_n: np.ndarray
    plan_force_n: np.ndarray
    feet_m: np.ndarray
    stance: np.ndarray
    plan_stance: np.ndarray
    fell_at_s: float | None
    diverged_at_s: float | None = None
    divergence: str | None = None


def follow_plan(
    plan: WholeBodyPlan, settings: SimSettings, cycles: int, friction: float
) -> tuple[WholeBodyRecord, FreeSimModel, WholeBodyGains]:
    """Simulate ``cycles`` cycles of ``plan`` (module docstring); the record, model and gains.

    Args:
        plan: The 3-D plan.
        settings: The referee's settings, complete (:meth:`SimSettings.for_leg_length`).
        cycles: Gait cycles to simulate: the steps that start within them
            (:func:`steps_in_cycles`).
        friction: The friction coefficient the controller keeps the forces within (the plan's).
    """
    physics = plan.physics
    sim = build_free_model(physics, settings)
    model = sim.model
    data = mujoco.MjData(model)
    dt = float(model.opt.timestep)
    period = plan.schedule.period_s
    n = steps_in_cycles(cycles, period, dt)
    t = np.arange(n) * dt
    cycle = np.floor(t / period + 1e-12)
    samples = plan.samples(np.clip(t - cycle * period, 0.0, np.nextafter(period, 0)))
    radius = sim.foot_radius_m
    q_plan = samples.q.copy()
    q_plan[0] += cycle * plan.stride_m
    q_plan[2] += radius
    feet_plan = samples.feet_m.copy()
    feet_plan[0] += cycle * plan.stride_m
    feet_plan[2] += radius
    schedule = plan.schedule
    position = t / schedule.step_s  # in nodes
    planned = schedule.stance_at(position)
    progress = np.vstack([schedule.swing_progress(leg, position) for leg in LEG_NAMES])
    shift = settings.schedule_shift_s
    shifted = schedule.stance_at((t - shift) / schedule.step_s)
    height_floor = 0.5 * float(plan.x[2].min())
    gains = whole_body_gains(
        physics, samples.q[:, 0], settings, friction, float(np.mean(plan.x[2]))
    )
    controller = WholeBodyController(physics, gains, sim.effort_limit_nm)

    sim.set_state(data, q_plan[:, 0], samples.v[:, 0])
    mujoco.mj_forward(model, data)
    nj, feet = physics.n_joints, len(physics.feet)
    q, v = np.zeros((model.nq, n)), np.zeros((physics.model.nv, n))
    qd_next, tau, feedback = (np.zeros((nj, n)) for _ in range(3))
    saturated = np.zeros((nj, n), dtype=bool)
    stance = np.zeros((feet, n), dtype=bool)
    force, feet_m = np.zeros((3, feet, n)), np.zeros((3, feet, n))
    foot_of = {int(g): i for i, g in enumerate(sim.foot_geom)}
    force6 = np.zeros(6)
    fell: float | None = None
    diverged_at: float | None = None
    failed: str | None = None
    clear_divergence(data)
    for k in range(n):
        q[:, k], v[:, k] = sim.pinocchio_state(data)
        feet_m[:, :, k] = data.geom_xpos[sim.foot_geom].T
        stance[:, k] = (
            planned[:, k] & shifted[:, k] if shift >= 0 else planned[:, k] | shifted[:, k]
        )
        if _fallen(q[:, k], q_plan[:, k], height_floor):
            fell = float(t[k])
            break
        out = controller.torques(
            q[:, k],
            v[:, k],
            q_plan[:, k],
            samples.v[:, k],
            samples.tau_nm[:, k],
            samples.forces_n[:, k],
            feet_plan[:, :, k],
            stance[:, k],
            progress[:, k],
        )
        data.ctrl[sim.actuators] = out.tau_nm
        tau[:, k], feedback[:, k], saturated[:, k] = out.tau_nm, out.feedback_nm, out.saturated
        mujoco.mj_step(model, data)
        failed = divergence(data)
        if failed is not None:  # MuJoCo reset the robot: nothing from here on is the plan's
            diverged_at = float(t[k])
            break
        # data now holds the contacts of state k and the velocity of state k + 1
        _contacts(model, data, foot_of, force[:, :, k], force6)
        qd_next[:, k] = data.qvel[sim.joint_dof]
    end = n if fell is None and diverged_at is None else k
    cut = slice(0, end)
    record = WholeBodyRecord(
        timestep_s=dt,
        t_s=t[cut],
        q=q[:, cut],
        v=v[:, cut],
        qd_next=qd_next[:, cut],
        tau_nm=tau[:, cut],
        feedback_nm=feedback[:, cut],
        saturated=saturated[:, cut],
        q_plan=q_plan[:, cut],
        feet_plan_m=feet_plan[:, :, cut],
        contact_force_n=force[:, :, cut],
        plan_force_n=samples.forces_n[:, cut].reshape(feet, 3, -1).transpose(1, 0, 2),
        feet_m=feet_m[:, :, cut],
        stance=stance[:, cut],
        plan_stance=planned[:, cut],
        fell_at_s=fell,
        diverged_at_s=diverged_at,
        divergence=failed,
    )
    return record, sim, gains


def _contacts(
    model: mujoco.MjModel,
    data: mujoco.MjData,
    foot_of: dict[int, int],
    out: np.ndarray,
    force6: np.ndarray,
) -> np.ndarray:
    """Fill ``out`` (3, 4) with the ground's force on each foot (world); which feet touch."""
    touching = np.zeros(out.shape[1], dtype=bool)
    for i in range(data.ncon):
        contact = data.contact[i]
        g1, g2 = int(contact.geom1), int(contact.geom2)
        foot = foot_of.get(g2, foot_of.get(g1))
        if foot is None:
            continue
        mujoco.mj_contactForce(model, data, i, force6)
        # the force of geom1 on geom2, along the contact normal (from geom1 to geom2) first
        world = contact.frame.reshape(3, 3).T @ force6[:3]
        out[:, foot] += -world if foot_of.get(g1) == foot else world
        touching[foot] = True
    return touching


def _fallen(q: np.ndarray, q_plan: np.ndarray, height_floor_m: float) -> bool:
    """Whether the trunk is below ``height_floor_m`` or tilted :data:`FALL_TILT_RAD` off plan."""
    if q[2] < height_floor_m:
        return True
    rot = pin.Quaternion(q[3:7]).toRotationMatrix()
    rot_plan = pin.Quaternion(q_plan[3:7]).toRotationMatrix()
    return float(np.linalg.norm(pin.log3(rot.T @ rot_plan))) > FALL_TILT_RAD
