"""The legs' joint servo: feed-forward torque from the plan plus a PD loop on each joint.

Per joint, at every time step::

    tau = tau_plan(t) + K_p (q_plan(t) - q) + K_d (qd_plan(t) - qd)

clipped to the URDF's effort limit. ``tau_plan`` is the energy pipeline's inverse-dynamics
torque (with the minimum-norm stance forces), so a model that were exact would need no PD
correction at all. The gains put the loop's natural frequency at ``f`` with damping ratio
``zeta`` on the joint's own inertia ``I`` (the diagonal of the leg's mass matrix, Pinocchio's
CRBA at the planned touch-down posture)::

    K_p = I (2 pi f)^2,      K_d = 2 zeta I (2 pi f)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from scalf_opt.model.robot import Robot
from scalf_opt.sim.plan import TrotPlan
from scalf_opt.sim.settings import SimSettings
from scalf_opt.types import LEG_NAMES


@dataclass(frozen=True)
class JointGains:
    """PD gains of one leg's (hip pitch, knee) joints.

    Attributes:
        kp_nm_per_rad: Stiffness K_p, shape (2,) [N m/rad].
        kd_nms_per_rad: Damping K_d, shape (2,) [N m s/rad].
    """

    kp_nm_per_rad: np.ndarray
    kd_nms_per_rad: np.ndarray


def servo_gains(robot: Robot, plan: TrotPlan, settings: SimSettings) -> dict[str, JointGains]:
    """Each leg's PD gains from its joint inertias at touch-down (module docstring)."""
    omega = 2 * math.pi * settings.servo_bandwidth_hz
    gains = {}
    for name in LEG_NAMES:
        leg = robot.leg(name)
        q_touchdown = plan.cycle.legs[name].stance.values["q"][:, 0]
        inertia = np.diag(pin.crba(leg.model, leg.model.createData(), q_touchdown)).copy()
        gains[name] = JointGains(
            kp_nm_per_rad=inertia * omega**2,
            kd_nms_per_rad=2 * settings.servo_damping_ratio * inertia * omega,
        )
    return gains
