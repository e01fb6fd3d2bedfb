"""The legs' servo: feed-forward torque from the plan plus feedback, in joint or trunk space.

Every joint's torque is the plan's feed-forward torque ``tau_plan`` (the energy pipeline's
inverse dynamics with its stance forces, so that a model that were exact would need no feedback)
plus a feedback term, clipped to the URDF's effort limit.

**Swing legs** (and every leg with ``stance_control = "joint"``): a PD loop on each joint::

    tau_fb = K_p (q_plan(t) - q) + K_d (qd_plan(t) - qd)

whose gains put the loop's natural frequency at ``f`` with damping ratio ``zeta`` on the joint's
own inertia ``I`` (the diagonal of the leg's mass matrix, Pinocchio's CRBA at the planned
touch-down posture)::

    K_p = I (2 pi f)^2,      K_d = 2 zeta I (2 pi f)

**Stance legs** (``stance_control = "trunk"``, the default): with the feet on the ground, the
stance joints move the trunk, whose inertia (the whole robot's, hundreds of times a swing leg's)
a joint loop tuned on the leg's own inertia does not see: such a loop is underdamped in stance
(ANYmal, SCalf: the stance phase's energy grew with the servo's stiffness), and four joint loops
on a trunk with three coordinates fight each other through the ground (the feet pushed each
other with hundreds of newtons). The stance feedback is therefore one PD loop on the trunk's
plan (x at the gait's speed, constant height, zero pitch), on the trunk's own inertia::

    F_fb = M_x ((2 pi f)^2 (x_plan - x) + 2 zeta (2 pi f) (xd_plan - xd))

``M_x`` the robot's inertia seen by the trunk coordinates with the stance feet fixed and the
swing joints held (``T^T M T``, ``T`` the map from the trunk's velocity to every coordinate's).
It is carried by the stance feet with minimum-norm foot forces ``g`` (``-J_x^T g = F_fb``,
``J_x`` the feet's (x, z) Jacobian over the trunk coordinates), so the feedback adds no force
between the feet, as the model's minimum-norm distribution has none; the joint torques are
``J_q^T g`` (``J_q`` the feet's Jacobian over their own joints).
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
    omega = 2 * math.pi * settings.value("servo_bandwidth_hz")
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


@dataclass(frozen=True)
class TrunkGains:
    """The stance feedback's loop on the trunk (module docstring).

    Attributes:
        omega_rad_s: Natural frequency ``2 pi f`` [rad/s].
        damping_ratio: ``zeta``.
    """

    omega_rad_s: float
    damping_ratio: float


def trunk_gains(settings: SimSettings) -> TrunkGains:
    """The trunk loop's frequency and damping: the servo's."""
    return TrunkGains(
        2 * math.pi * settings.value("servo_bandwidth_hz"), settings.servo_damping_ratio
    )


def stance_feedback_nm(
    jac_trunk: np.ndarray,
    jac_joints: np.ndarray,
    mass_matrix: np.ndarray,
    trunk_error: np.ndarray,
    trunk_rate_error: np.ndarray,
    gains: TrunkGains,
) -> np.ndarray:
    """The stance legs' feedback torques from the trunk's error (module docstring).

    Args:
        jac_trunk: ``J_x``, the stance feet's (x, z) velocity over the trunk's (x, z, pitch)
            rates, shape (2 s, 3) for ``s`` stance feet.
        jac_joints: ``J_q``, block diagonal, the feet's (x, z) velocity over their own legs'
            joint rates, shape (2 s, 2 s).
        mass_matrix: The robot's inertia over (trunk, stance joints), shape (3 + 2 s, 3 + 2 s),
            the swing joints held.
        trunk_error: ``x_plan - x`` [m, m, rad].
        trunk_rate_error: ``xd_plan - xd`` [m/s, m/s, rad/s].
        gains: The loop.

    Returns:
        The stance joints' torques, shape (2 s,), legs in the order of the rows [N m].
    """
    to_joints = -np.linalg.solve(jac_joints, jac_trunk)  # qd_stance = G xd, feet fixed
    t_map = np.vstack([np.eye(3), to_joints])
    inertia = t_map.T @ mass_matrix @ t_map
    w, z = gains.omega_rad_s, gains.damping_ratio
    force = inertia @ (w**2 * trunk_error + 2 * z * w * trunk_rate_error)
    # minimum norm (no force between the feet): f = -J_x (J_x^T J_x)^-1 F, J_x of full column
    # rank with two feet apart; one 3 x 3 solve per step instead of an SVD (a fifth of the
    # simulation's time went to the pseudo-inverse)
    try:
        foot = -jac_trunk @ np.linalg.solve(jac_trunk.T @ jac_trunk, force)
    except np.linalg.LinAlgError:  # the feet in one point: the pseudo-inverse's least squares
        foot = -np.linalg.pinv(jac_trunk.T) @ force
    return jac_joints.T @ foot
