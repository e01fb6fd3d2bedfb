"""Step the MuJoCo trot and record it.

The simulation starts at cycle time 0, the instant RF and LH touch down and LF and RH lift off,
with every leg on its plan (angles and rates), the trunk moving forward at the gait's speed and
so high that the stance feet just touch the ground. Each step (semi-implicit Euler, MuJoCo's
default) the servo (:mod:`~scalf_opt.sim.control`) sets the joint torques from the state at the
step's start; the record holds, per step ``k``:

* the state at the step's start (time ``t_k``, trunk pose, joint angles), the torques applied
  over the step and the joint rates at its end, ``qd_{k+1}``: semi-implicit Euler moves the
  joints by ``qd_{k+1} dt``, so ``tau_k qd_{k+1} dt`` is exactly the work of step ``k``;
* per foot, the ground's force on it in the world frame (x, z) and the speed along x of the
  foot's material point at the contact (zero off the ground): the foot's slip;
* for the energy balance of the whole robot, the kinetic plus potential energy at ``t_k`` and the
  power of the actuators and of the other forces (contacts, joint limits, joint damping) at the
  step's mean velocity.

After every step the run reads MuJoCo's own check of the state (:mod:`~scalf_opt.sim.divergence`):
when MuJoCo reports that the integration diverged (and has reset the robot to its initial pose),
the run stops there, and the record's figures from that step on are NaN.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

import mujoco
import numpy as np

from scalf_opt.sim.control import JointGains, TrunkGains, stance_feedback_nm
from scalf_opt.sim.divergence import clear_divergence, divergence
from scalf_opt.sim.mujoco_model import SimModel
from scalf_opt.sim.plan import TrotPlan
from scalf_opt.types import LEG_NAMES


@dataclass(frozen=True)
class SimRecord:
    """One simulated run, step by step (n steps; arrays along the last axis).

    A run MuJoCo flagged as diverged stopped at the step it flagged (``diverged_at_s``): from
    that step on every float array below is NaN and no joint saturates.

    Attributes:
        t_s: Time at each step's start [s], shape (n,).
        timestep_s: Step [s].
        trunk: Trunk x [m], z [m] and pitch [rad] at each step's start, shape (3, n).
        q_rad: Per leg, (hip pitch, knee) angles at each step's start, (2, n) [rad].
        qd_rad_s: Per leg, joint rates at each step's end, (2, n) [rad/s].
        tau_nm: Per leg, joint torques applied over each step (after the effort limit), (2, n).
        saturated: Per leg, whether the servo asked more than the effort limit, (2, n).
        grf_n: Per leg, ground force on the foot in the world frame (x, z), (2, n) [N].
        slip_m_s: Per leg, |x speed| of the foot's contact point, (n,) [m/s] (0 off the ground).
        energy_j: Kinetic + potential energy of the robot at each step's start and at the end,
            shape (n + 1,) [J].
        actuator_power_w: Power of all joint torques at each step's mean velocity, (n,) [W].
        constraint_power_w: Power of the constraint forces (contacts, joint limits) and of the
            URDF's joint damping, the same way, (n,) [W].
        start_trunk_height_m: The trunk's height at the start, feet just on the ground [m].
        diverged_at_s: When the step in which MuJoCo's integration diverged started [s]
            (:mod:`~scalf_opt.sim.divergence`), ``None`` when it did not.
        divergence: Which of MuJoCo's checks failed then, in words (``bad accelerations,
            MuJoCo's BADQACC``), ``None`` when none did.
    """

    t_s: np.ndarray
    timestep_s: float
    trunk: np.ndarray
    q_rad: dict[str, np.ndarray]
    qd_rad_s: dict[str, np.ndarray]
    tau_nm: dict[str, np.ndarray]
    saturated: dict[str, np.ndarray]
    grf_n: dict[str, np.ndarray]
    slip_m_s: dict[str, np.ndarray]
    energy_j: np.ndarray
    actuator_power_w: np.ndarray
    constraint_power_w: np.ndarray
    start_trunk_height_m: float
    diverged_at_s: float | None = None
    divergence: str | None = None

    def in_contact(self, leg: str) -> np.ndarray:
        """Whether the foot of ``leg`` presses on the ground, shape (n,)."""
        return self.grf_n[leg][1] > 0.0


def _start(sim: SimModel, plan: TrotPlan, data: mujoco.MjData) -> float:
    """Put the robot on its plan at t = 0; return the trunk's height."""
    model = sim.model
    for leg in LEG_NAMES:
        ref = plan.sample(leg, np.zeros(1))
        data.qpos[sim.leg_qpos[leg]] = ref["q"][:, 0]
        data.qvel[sim.leg_dof[leg]] = ref["qd"][:, 0]
    data.qvel[sim.trunk_dof[0]] = plan.cycle.gait.speed_m_s
    mujoco.mj_kinematics(model, data)
    stance = [leg for leg in LEG_NAMES if plan.in_stance(leg, np.zeros(1))[0]]
    lowest = min(float(data.geom_xpos[sim.foot_geom[leg]][2]) for leg in stance)
    height = sim.foot_radius_m - lowest
    data.qpos[sim.trunk_qpos[1]] = height
    mujoco.mj_forward(model, data)
    return height


def _stance_feedback(
    feedback: np.ndarray,
    sim: SimModel,
    data: mujoco.MjData,
    on_ground: list[int],
    jacp: np.ndarray,
    mass: np.ndarray,
    gains: TrunkGains,
    trunk_error: np.ndarray,
    trunk_rate_error: np.ndarray,
) -> None:
    """Replace the stance legs' rows of ``feedback`` by the trunk loop's torques.

    ``on_ground`` indexes :data:`LEG_NAMES`; ``feedback`` holds two rows per leg in that order
    (:func:`~scalf_opt.sim.control.stance_feedback_nm`).
    """
    model = sim.model
    legs = [LEG_NAMES[i] for i in on_ground]
    s = len(legs)
    jac_trunk, jac_joints = np.zeros((2 * s, 3)), np.zeros((2 * s, 2 * s))
    for i, leg in enumerate(legs):
        mujoco.mj_jac(
            model, data, jacp, None, data.geom_xpos[sim.foot_geom[leg]], sim.foot_body[leg]
        )
        rows = jacp[[0, 2]]
        jac_trunk[2 * i : 2 * i + 2] = rows[:, sim.trunk_dof]
        jac_joints[2 * i : 2 * i + 2, 2 * i : 2 * i + 2] = rows[:, sim.leg_dof[leg]]
    mujoco.mj_fullM(model, data, mass)
    dofs = np.concatenate([sim.trunk_dof, *(sim.leg_dof[leg] for leg in legs)])
    rows = np.concatenate([np.arange(2 * i, 2 * i + 2) for i in on_ground])
    feedback[rows] = stance_feedback_nm(
        jac_trunk, jac_joints, mass[np.ix_(dofs, dofs)], trunk_error, trunk_rate_error, gains
    )


def _legs_stacked(*per_leg: Mapping[str, np.ndarray]) -> list[np.ndarray]:
    """Each per-leg mapping's arrays one after the other, legs in :data:`LEG_NAMES` order."""
    return [np.concatenate([values[leg] for leg in LEG_NAMES]) for values in per_leg]


def _record_contacts(
    sim: SimModel,
    data: Any,
    foot_leg: dict[int, str],
    k: int,
    grf: dict[str, np.ndarray],
    slip: dict[str, np.ndarray],
    force6: np.ndarray,
    jacp: np.ndarray,
) -> None:
    """Step ``k``'s foot contacts: each foot's ground force (x, z) and its slip speed [m/s].

    ``force6`` and ``jacp`` are scratch arrays (reused: this runs at every step).
    """
    model = sim.model
    for i in range(data.ncon):
        contact = data.contact[i]
        g1, g2 = int(contact.geom1), int(contact.geom2)
        leg = foot_leg.get(g2) or foot_leg.get(g1)
        if leg is None:
            continue
        mujoco.mj_contactForce(model, data, i, force6)
        # the force of geom1 on geom2, along the contact normal (from geom1 to geom2) first
        force = contact.frame.reshape(3, 3).T @ force6[:3]
        if g1 == sim.foot_geom[leg]:
            force = -force
        grf[leg][:, k] += force[[0, 2]]
        mujoco.mj_jac(model, data, jacp, None, contact.pos, sim.foot_body[leg])
        slip[leg][k] = abs(float(jacp[0] @ data.qvel))


def _stance_loop_legs(scheduled: np.ndarray) -> list[int]:
    """The legs (indices into :data:`LEG_NAMES`) the controller's schedule puts in stance.

    With the plan's own schedule, exactly the planned stance legs. A schedule whose touch-downs
    run early switches a leg to the stance loop while its foot is still in the air, as a
    controller that detects contact too early does; one that runs late keeps a landed leg on its
    swing loop (:meth:`~scalf_opt.sim.plan.TrotPlan.scheduled_stance`).
    """
    return [i for i in range(len(LEG_NAMES)) if scheduled[i]]


def _by_leg(rows: np.ndarray) -> dict[str, np.ndarray]:
    """The stacked joint rows (two per leg, :data:`LEG_NAMES` order) split by leg."""
    return {leg: rows[2 * i : 2 * i + 2] for i, leg in enumerate(LEG_NAMES)}


def _blank_from(stop: int, records: tuple[np.ndarray, ...], saturated: np.ndarray) -> None:
    """Blank the records from step ``stop`` on (NaN; ``saturated`` False): MuJoCo diverged."""
    for values in records:
        values[..., stop:] = np.nan
    saturated[:, stop:] = False


def simulate(
    sim: SimModel,
    plan: TrotPlan,
    gains: dict[str, JointGains],
    cycles: int,
    trunk: TrunkGains | None = None,
    schedule_shift_s: float = 0.0,
) -> SimRecord:
    """Simulate ``cycles`` gait cycles of the plan with the servo ``gains``.

    Args:
        sim: The MuJoCo model.
        plan: The planned trot.
        gains: Every leg's joint loop.
        cycles: Gait cycles to simulate.
        trunk: The stance legs' loop on the trunk, or ``None``: the joint loops in stance too
            (:mod:`~scalf_opt.sim.control`).
        schedule_shift_s: How late the controller switches a leg from its swing feedback to the
            stance feedback against the planned touch-down [s]
            (:class:`~scalf_opt.sim.settings.SimSettings`).
    """
    model = sim.model
    data = mujoco.MjData(model)
    dt = float(model.opt.timestep)
    n = round(cycles * plan.cycle.gait.period_s / dt)
    t = np.arange(n) * dt
    refs = [plan.sample(leg, t) for leg in LEG_NAMES]
    q_ref, qd_ref, tau_ff = (np.vstack([r[k] for r in refs]) for k in ("q", "qd", "tau"))
    qpos_i, dof_i, act_i, limit = _legs_stacked(
        sim.leg_qpos, sim.leg_dof, sim.leg_actuators, sim.effort_limit_nm
    )
    kp, kd = _legs_stacked(
        {leg: g.kp_nm_per_rad for leg, g in gains.items()},
        {leg: g.kd_nms_per_rad for leg, g in gains.items()},
    )
    foot_leg = {geom: leg for leg, geom in sim.foot_geom.items()}
    # the controller's contact schedule: the plan's, its touch-downs shifted
    stance = np.array([plan.scheduled_stance(leg, t, schedule_shift_s) for leg in LEG_NAMES])
    mass = np.zeros((model.nv, model.nv))
    speed = plan.cycle.gait.speed_m_s

    start_height = _start(sim, plan, data)
    trunk_pose = np.zeros((3, n))
    q, qd, tau = (np.zeros((qpos_i.size, n)) for _ in range(3))
    saturated = np.zeros((qpos_i.size, n), dtype=bool)
    grf = {leg: np.zeros((2, n)) for leg in LEG_NAMES}
    slip = {leg: np.zeros(n) for leg in LEG_NAMES}
    energy = np.zeros(n + 1)
    p_act, p_con = np.zeros(n), np.zeros(n)
    force6 = np.zeros(6)
    jacp = np.zeros((3, model.nv))
    diverged: tuple[int, str] | None = None
    clear_divergence(data)
    for k in range(n):
        trunk_pose[:, k] = data.qpos[sim.trunk_qpos]
        q[:, k] = data.qpos[qpos_i]
        v_start = data.qvel.copy()
        feedback = kp * (q_ref[:, k] - q[:, k]) + kd * (qd_ref[:, k] - v_start[dof_i])
        on_ground = _stance_loop_legs(stance[:, k])
        if trunk is not None and on_ground:
            _stance_feedback(
                feedback,
                sim,
                data,
                on_ground,
                jacp,
                mass,
                trunk,
                np.array([speed * t[k], start_height, 0.0]) - trunk_pose[:, k],
                np.array([speed, 0.0, 0.0]) - v_start[sim.trunk_dof],
            )
        demand = tau_ff[:, k] + feedback
        saturated[:, k] = np.abs(demand) > limit
        data.ctrl[act_i] = np.clip(demand, -limit, limit)
        mujoco.mj_step(model, data)
        failed = divergence(data)
        if failed is not None:  # MuJoCo reset the robot: nothing from here on is the plan's
            diverged = (k, failed)
            break
        # data now holds the forces and contacts of state k and the velocity of state k + 1
        energy[k] = data.energy[0] + data.energy[1]
        v_mid = 0.5 * (v_start + data.qvel)
        p_act[k] = data.qfrc_actuator @ v_mid
        p_con[k] = (data.qfrc_constraint + data.qfrc_passive) @ v_mid
        tau[:, k] = data.actuator_force[act_i]
        qd[:, k] = data.qvel[dof_i]
        _record_contacts(sim, data, foot_leg, k, grf, slip, force6, jacp)
    if diverged is None:
        mujoco.mj_forward(model, data)
        energy[n] = data.energy[0] + data.energy[1]
    else:
        _blank_from(
            diverged[0],
            (trunk_pose, q, qd, tau, energy, p_act, p_con, *grf.values(), *slip.values()),
            saturated,
        )

    return SimRecord(
        t_s=t,
        timestep_s=dt,
        trunk=trunk_pose,
        q_rad=_by_leg(q),
        qd_rad_s=_by_leg(qd),
        tau_nm=_by_leg(tau),
        saturated=_by_leg(saturated),
        grf_n=grf,
        slip_m_s=slip,
        energy_j=energy,
        actuator_power_w=p_act,
        constraint_power_w=p_con,
        start_trunk_height_m=start_height,
        diverged_at_s=None if diverged is None else float(t[diverged[0]]),
        divergence=None if diverged is None else diverged[1],
    )
