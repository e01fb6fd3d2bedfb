"""What the plan costs when the robot follows it exactly: MuJoCo's inverse dynamics of the plan.

The referee's own prediction, without a servo: at every time step of one gait cycle the whole
simulated robot (trunk and all four legs) is put on the plan (the trunk at the gait's speed, at
constant height, level; every joint at its planned angle, rate and acceleration), and MuJoCo's
inverse dynamics (contacts off) gives the generalized forces the motion needs. The trunk's share
must come from the stance feet: their (x, z) forces ``f`` solve ``J_x^T f = Q_trunk`` with the
least norm (no force between the feet, as the model's distribution), and each joint's torque is
``Q_joint - J_q^T f`` (swing legs: ``Q_joint``). The joint energy then goes through the model's
power formula.

So a simulated run splits into two differences: model vs this (the energy model's loads: the
trunk-only model leaves out the legs' weight and inertial reactions) and this vs the simulation
(what the servo and the contacts add: the referee's own share).
"""

from __future__ import annotations

from typing import Any

import mujoco
import numpy as np

from scalf_opt.energy.pipeline import EnergyPipeline
from scalf_opt.sim.mujoco_model import SimModel
from scalf_opt.sim.plan import TrotPlan
from scalf_opt.types import LEG_NAMES


def plan_torques(
    sim: SimModel, plan: TrotPlan, t_s: np.ndarray, trunk_height_m: float
) -> tuple[dict[str, dict[str, np.ndarray]], dict[str, np.ndarray]]:
    """Every leg's planned motion and the torques it needs (module docstring).

    Args:
        sim: The MuJoCo model (its contact flag is restored after use).
        plan: The plan.
        t_s: Times [s], shape (n,).
        trunk_height_m: The trunk's height (gravity's work on it does not depend on it).

    Returns:
        Per leg ``{"q", "qd", "tau"}``, each (2, n) [rad, rad/s, N m], and per leg the
        ground's (x, z) force on its foot, (2, n) [N] (zero in swing).
    """
    model = sim.model
    data = mujoco.MjData(model)
    speed = plan.cycle.gait.speed_m_s
    refs = {leg: plan.sample(leg, t_s, ("q", "qd", "qdd")) for leg in LEG_NAMES}
    stance = {leg: plan.in_stance(leg, t_s) for leg in LEG_NAMES}
    tau = {leg: np.zeros((2, t_s.size)) for leg in LEG_NAMES}
    grf = {leg: np.zeros((2, t_s.size)) for leg in LEG_NAMES}
    jacp = np.zeros((3, model.nv))
    flags = model.opt.disableflags
    model.opt.disableflags = flags | mujoco.mjtDisableBit.mjDSBL_CONTACT
    try:
        for k, t in enumerate(t_s):
            data.qpos[sim.trunk_qpos] = (speed * t, trunk_height_m, 0.0)
            data.qvel[sim.trunk_dof] = (speed, 0.0, 0.0)
            data.qacc[sim.trunk_dof] = 0.0
            for leg in LEG_NAMES:
                data.qpos[sim.leg_qpos[leg]] = refs[leg]["q"][:, k]
                data.qvel[sim.leg_dof[leg]] = refs[leg]["qd"][:, k]
                data.qacc[sim.leg_dof[leg]] = refs[leg]["qdd"][:, k]
            mujoco.mj_inverse(model, data)
            generalized = data.qfrc_inverse.copy()
            on_ground = [leg for leg in LEG_NAMES if stance[leg][k]]
            forces = np.zeros(2 * len(on_ground))
            jac_joints = []
            if on_ground:
                jac_trunk = np.zeros((2 * len(on_ground), 3))
                for i, leg in enumerate(on_ground):
                    point = data.geom_xpos[sim.foot_geom[leg]]
                    mujoco.mj_jac(model, data, jacp, None, point, sim.foot_body[leg])
                    jac_trunk[2 * i : 2 * i + 2] = jacp[[0, 2]][:, sim.trunk_dof]
                    jac_joints.append(jacp[[0, 2]][:, sim.leg_dof[leg]])
                forces = np.linalg.pinv(jac_trunk.T) @ generalized[sim.trunk_dof]
            for leg in LEG_NAMES:
                tau[leg][:, k] = generalized[sim.leg_dof[leg]]
            for i, leg in enumerate(on_ground):
                f = forces[2 * i : 2 * i + 2]
                tau[leg][:, k] -= jac_joints[i].T @ f
                grf[leg][:, k] = f
    finally:
        model.opt.disableflags = flags
    motion = {
        leg: {"q": refs[leg]["q"], "qd": refs[leg]["qd"], "tau": tau[leg]} for leg in LEG_NAMES
    }
    return motion, grf


def plan_inverse_dynamics(
    sim: SimModel, plan: TrotPlan, pipeline: EnergyPipeline, dt_s: float, trunk_height_m: float
) -> dict[str, Any]:
    """The plan's joint energy per cycle, per leg and phase, and its mean stance forces.

    One cycle on the simulation's step ``dt_s``, summed like the simulation's record (power
    times step), through the model's power formula.
    """
    gait = plan.cycle.gait
    t = np.arange(round(gait.period_s / dt_s)) * dt_s
    motion, grf = plan_torques(sim, plan, t, trunk_height_m)
    energy: dict[str, Any] = {}
    force: dict[str, float] = {}
    for leg in LEG_NAMES:
        m = motion[leg]
        fn = pipeline.physics(leg).power_function(pipeline.accounting).map(t.size)
        power = np.array(fn(m["q"], m["qd"], m["tau"])[0]).sum(axis=0)
        stance = plan.in_stance(leg, t)
        energy[leg] = {
            "stance": float(power[stance].sum() * dt_s),
            "swing": float(power[~stance].sum() * dt_s),
        }
        force[leg] = float(grf[leg][1][stance].mean())
    return {"joint_energy_per_phase_j": energy, "stance_force_mean_n": force}
