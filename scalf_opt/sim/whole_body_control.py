r"""The 3-D referee's controller: the plan's feed-forward, joint impedance, trunk feedback by a QP.

The kind of whole-body controller legged robots run, here as a referee of a 3-D plan
(:class:`~scalf_opt.energy.whole_body_plan.WholeBodyPlan`). Every joint's torque is the plan's
feed-forward torque ``tau_ff`` (Pinocchio's inverse dynamics of the plan with the plan's contact
forces: a model that were exact would need nothing else) plus feedback, clipped to the URDF's
effort limit:

* **swing legs** (and every leg in flight): joint impedance ``K_p (q_t - q) + K_d (qd_plan -
  qd)``, ``K_p = I (2 pi f)^2``, ``K_d = 2 zeta I (2 pi f)`` on the inertia ``I`` each joint meets
  with everything else free, ``1 / (M^-1)_jj`` at the plan's start, ``f`` and ``zeta`` the servo's
  (:mod:`scalf_opt.sim.settings`). The trunk is free to turn about the line of its stance feet, so
  a swing joint moves less inertia than the locked ``M_jj`` (about half, on Go1): gains on
  ``M_jj`` made Go1's abduction joints and the trunk's roll ring at the time step's Nyquist
  frequency at twice the servo's gains. The target ``q_t`` steers the foot in the world, not the
  joints: the plan's foot position moved by the trunk's horizontal offset from its plan and by
  Raibert's ``sqrt(h / g)`` times the trunk's horizontal velocity error (``h`` the stance height),
  blended in over the swing, one Newton step of the leg's inverse kinematics from where its joints
  are. Tracking the plan's joint angles instead puts a foot on the wrong side of a trunk that
  rolls (the leg turns with it): on Go1's 3-D optimum the trunk then fell sideways, its error
  growing about sevenfold per cycle, the rate at which a body ``h`` high topples about the line of
  its two stance feet;
* **stance legs**: no joint loop (four joint loops on one trunk fight each other through the
  ground, :mod:`scalf_opt.sim.control`), but the trunk's posture and momentum feedback: the
  generalized force on the trunk

  .. math:: Q = M_{bb} \left((2\pi f_b)^2 e + 2\zeta (2\pi f_b)\dot e\right),

  ``f_b`` = :data:`TRUNK_BANDWIDTH_OVER_SERVO` times the servo's ``f``, ``e`` the trunk's
  position and orientation error (``R^T (p_plan - p)`` and ``log(R^T
  R_plan)``, trunk axes), ``M_bb`` the whole robot's inertia seen by the trunk with the joints
  held, is asked of extra stance forces ``df`` found by a small QP (CasADi's active-set ``qrqp``):

  .. math:: \min_{df} \|S (A\,df - Q)\|^2 + \lambda \|df\|^2 \quad\text{s.t.}\quad
            f_{plan} + df \in \text{friction pyramid},\ df = 0 \text{ on swing feet},

  ``A`` stacking the stance feet's Jacobians over the trunk's velocity (``J_b^T``), ``S``
  weighting moments by the inverse of the stance height (newtons against newton-metres), and the
  small ``lambda`` choosing, among equal fits, the least extra force. Two diagonal feet cannot
  push a moment about the line joining them: the QP leaves that part of ``Q`` undone (the trunk
  rolls about the diagonal, as a trotting robot does), it does not invent it. The stance
  joints then carry ``-J_q^T df``. Unlike the sagittal referee's minimum-norm split, nothing
  forbids the QP a force between the feet.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import casadi as ca
import numpy as np
import pinocchio as pin

from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.locomotion.forces import GRAVITY_M_S2
from scalf_opt.sim.settings import SimSettings

TRUNK_BANDWIDTH_OVER_SERVO = 0.125
"""The trunk loop's natural frequency over the servo's: the loop acts through the stance legs
and their contacts, so it stays well under them (a cascade). On Go1's 3-D optimum the simulated
energy moved by under a point between 2 and 20 Hz; at the servo's own 42.5 Hz the loop rang at
the time step's Nyquist frequency."""

FORCE_REGULARISATION = 1e-4
"""``lambda``: the QP's weight on the extra force's size, against a fit weighted to order one."""

PYRAMID_ROWS = np.array([[1.0, 0.0, -1.0], [-1.0, 0.0, -1.0], [0.0, 1.0, -1.0], [0.0, -1.0, -1.0]])
"""The friction pyramid's rows at unit friction: ``row . (f_x, f_y, mu f_z) <= 0``."""


@dataclass(frozen=True)
class WholeBodyGains:
    """The controller's gains (module docstring).

    Attributes:
        joint_kp: Each joint's stiffness ``K_p`` (n_joints,) [N m/rad].
        joint_kd: Each joint's damping ``K_d`` (n_joints,) [N m s/rad].
        trunk_omega_rad_s: The trunk loop's natural frequency ``2 pi f`` [rad/s].
        trunk_damping_ratio: Its damping ratio ``zeta``.
        friction: The friction coefficient the QP keeps the forces within (the plan's).
        moment_arm_m: The stance height that weighs moments against forces [m].
        placement_time_s: Raibert's foot-placement gain ``sqrt(h / g)`` [s].
    """

    joint_kp: np.ndarray
    joint_kd: np.ndarray
    trunk_omega_rad_s: float
    trunk_damping_ratio: float
    friction: float
    moment_arm_m: float
    placement_time_s: float


def whole_body_gains(
    physics: WholeBodyPhysics,
    q_start: np.ndarray,
    settings: SimSettings,
    friction: float,
    moment_arm_m: float,
) -> WholeBodyGains:
    """The gains at the plan's start ``q_start`` (Pinocchio's ``q``); ``settings`` complete."""
    model = physics.model
    mass = pin.crba(model, model.createData(), q_start)
    mass = np.triu(mass) + np.triu(mass, 1).T
    inertia = 1.0 / np.diag(np.linalg.inv(mass))[6:]
    omega = 2 * math.pi * settings.value("servo_bandwidth_hz")
    zeta = settings.servo_damping_ratio
    return WholeBodyGains(
        joint_kp=inertia * omega**2,
        joint_kd=2 * zeta * inertia * omega,
        trunk_omega_rad_s=TRUNK_BANDWIDTH_OVER_SERVO * omega,
        trunk_damping_ratio=zeta,
        friction=friction,
        moment_arm_m=moment_arm_m,
        placement_time_s=math.sqrt(moment_arm_m / GRAVITY_M_S2),
    )


@dataclass(frozen=True)
class ControlOutput:
    """One step's torques and what they are made of.

    Attributes:
        tau_nm: The torques applied, clipped to the effort limit (n_joints,) [N m].
        feedback_nm: Their feedback part (joint impedance and the stance legs' ``-J_q^T df``)
            before clipping (n_joints,) [N m].
        extra_force_n: The QP's extra stance forces ``df`` (12,) [N], world axes, on the robot.
        saturated: Which joints asked beyond their effort limit (n_joints,).
    """

    tau_nm: np.ndarray
    feedback_nm: np.ndarray
    extra_force_n: np.ndarray
    saturated: np.ndarray


class WholeBodyController:
    """The controller of one robot (module docstring); :meth:`torques` once per step."""

    def __init__(self, physics: WholeBodyPhysics, gains: WholeBodyGains, effort_nm: np.ndarray):
        """``effort_nm``: each joint's effort limit (``inf`` where none) [N m]."""
        self.physics = physics
        self.gains = gains
        self.effort_nm = effort_nm
        self._data = physics.model.createData()
        self._feet = [physics.model.getFrameId(foot) for foot in physics.feet]
        self._joint_leg = np.array(physics.joint_legs)

    @cached_property
    def _qp(self) -> ca.Function:
        n = 3 * len(self._feet)
        return ca.conic(
            "trunk_forces",
            "qrqp",
            {"h": ca.Sparsity.dense(n, n), "a": ca.Sparsity.dense(4 * len(self._feet), n)},
            {
                "print_iter": False,
                "print_header": False,
                "print_info": False,
                "error_on_fail": False,
            },
        )

    @cached_property
    def _pyramid(self) -> np.ndarray:
        """The pyramid's rows over all feet's forces (4 per foot, 12 columns)."""
        rows = PYRAMID_ROWS * np.array([1.0, 1.0, self.gains.friction])
        return np.kron(np.eye(len(self._feet)), rows)

    def torques(
        self,
        q: np.ndarray,
        v: np.ndarray,
        q_plan: np.ndarray,
        v_plan: np.ndarray,
        tau_ff: np.ndarray,
        plan_forces: np.ndarray,
        plan_feet: np.ndarray,
        stance: np.ndarray,
        swing_progress: np.ndarray,
    ) -> ControlOutput:
        """The joint torques at the state ``(q, v)`` (Pinocchio's) for the plan's instant.

        Args:
            q: The robot's configuration (Pinocchio's ``q``).
            v: Its velocity (Pinocchio's ``v``).
            q_plan: The plan's configuration at this instant.
            v_plan: The plan's velocity at this instant.
            tau_ff: The plan's joint torques (n_joints,) [N m].
            plan_forces: The plan's contact forces (12,) [N], world axes, on the robot.
            plan_feet: The plan's foot positions (3, 4) [m], world (the spheres' centres).
            stance: Which legs the controller holds in stance (4,), :attr:`physics.feet` order.
            swing_progress: How far each swing has gone, 0 at lift-off to 1 at touch-down (4,)
                (any value in stance).
        """
        model, data, gains = self.physics.model, self._data, self.gains
        pin.computeJointJacobians(model, data, q)
        pin.updateFramePlacements(model, data)
        jacobians = [
            pin.getFrameJacobian(model, data, fid, pin.LOCAL_WORLD_ALIGNED)[:3]
            for fid in self._feet
        ]
        rot = pin.Quaternion(q[3:7]).toRotationMatrix()
        rot_plan = pin.Quaternion(q_plan[3:7]).toRotationMatrix()
        target = self._swing_targets(
            q, v, q_plan, v_plan, (rot, rot_plan), plan_feet, jacobians, stance, swing_progress
        )
        swing_joint = ~stance[self._joint_leg]
        feedback = np.where(
            swing_joint,
            gains.joint_kp * (target - q[7:]) + gains.joint_kd * (v_plan[6:] - v[6:]),
            0.0,
        )
        extra = np.zeros(3 * len(self._feet))
        if stance.any():
            inertia = pin.crba(model, data, q)[:6, :6]
            inertia = np.triu(inertia) + np.triu(inertia, 1).T
            extra = self._extra_forces(
                self._trunk_force(inertia, q, v, q_plan, v_plan, (rot, rot_plan)),
                jacobians,
                plan_forces,
                stance,
            )
            for i, jac in enumerate(jacobians):
                if stance[i]:
                    feedback -= jac[:, 6:].T @ extra[3 * i : 3 * i + 3]
        wanted = tau_ff + feedback
        tau = np.clip(wanted, -self.effort_nm, self.effort_nm)
        return ControlOutput(tau, feedback, extra, np.abs(wanted) > self.effort_nm)

    def _swing_targets(
        self,
        q: np.ndarray,
        v: np.ndarray,
        q_plan: np.ndarray,
        v_plan: np.ndarray,
        rotations: tuple[np.ndarray, np.ndarray],
        plan_feet: np.ndarray,
        jacobians: list[np.ndarray],
        stance: np.ndarray,
        swing_progress: np.ndarray,
    ) -> np.ndarray:
        """The joints' targets (n_joints,) [rad]: the plan's, and for swing legs the foot's.

        A swing foot is steered in the world (module docstring): towards the plan's foot
        position moved by the trunk's horizontal offset from its plan and by Raibert's
        ``sqrt(h / g)`` times the trunk's horizontal velocity error, both blended in over the
        swing (``3 s^2 - 2 s^3``), the joints' target one Newton step of the leg's inverse
        kinematics from where they are.
        """
        target = q_plan[7:].copy()
        if stance.all():
            return target
        data = self._data
        rot, rot_plan = rotations  # the trunk's and the plan's (world from trunk)
        velocity_error = rot @ v[:3] - rot_plan @ v_plan[:3]
        offset = q[:3] - q_plan[:3] + self.gains.placement_time_s * velocity_error
        offset[2] = 0.0
        for i, (jac, fid) in enumerate(zip(jacobians, self._feet, strict=True)):
            if stance[i]:
                continue
            s = float(np.clip(swing_progress[i], 0.0, 1.0))
            goal = plan_feet[:, i] + (3 * s**2 - 2 * s**3) * offset
            joints = np.flatnonzero(self._joint_leg == i)
            miss = goal - data.oMf[fid].translation
            step = np.linalg.lstsq(jac[:, 6 + joints], miss, rcond=None)[0]
            target[joints] = q[7 + joints] + step
        return target

    def _trunk_force(
        self,
        inertia: np.ndarray,
        q: np.ndarray,
        v: np.ndarray,
        q_plan: np.ndarray,
        v_plan: np.ndarray,
        rotations: tuple[np.ndarray, np.ndarray],
    ) -> np.ndarray:
        """``Q`` (6,): the trunk's feedback as a force and moment in its own axes."""
        rot, rot_plan = rotations  # the trunk's and the plan's (world from trunk)
        error = np.r_[rot.T @ (q_plan[:3] - q[:3]), pin.log3(rot.T @ rot_plan)]
        rate_error = np.r_[
            rot.T @ (rot_plan @ v_plan[:3]) - v[:3], rot.T @ (rot_plan @ v_plan[3:6]) - v[3:6]
        ]
        w, z = self.gains.trunk_omega_rad_s, self.gains.trunk_damping_ratio
        return inertia @ (w**2 * error + 2 * z * w * rate_error)

    def _extra_forces(
        self,
        wrench: np.ndarray,
        jacobians: list[np.ndarray],
        plan_forces: np.ndarray,
        stance: np.ndarray,
    ) -> np.ndarray:
        """The QP's ``df`` (12,) for the trunk's ``wrench`` (module docstring)."""
        n = 3 * len(self._feet)
        a = np.hstack([jac[:, :6].T for jac in jacobians])  # (6, 12)
        weight = np.r_[np.ones(3), np.full(3, 1.0 / self.gains.moment_arm_m)] ** 2
        hessian = 2 * (a.T @ (weight[:, None] * a) + FORCE_REGULARISATION * np.eye(n))
        gradient = -2 * a.T @ (weight * wrench)
        on = np.repeat(stance, 3)
        lower = np.where(on, -np.inf, 0.0)
        lower[2::3] = np.where(stance, -plan_forces[2::3], 0.0)
        upper = np.where(on, np.inf, 0.0)
        pyramid = self._pyramid
        solution = self._qp(
            h=hessian,
            g=gradient,
            a=pyramid,
            lba=-np.inf,
            uba=-pyramid @ plan_forces,
            lbx=lower,
            ubx=upper,
        )
        if not self._qp.stats()["success"]:
            return np.zeros(n)  # the plan's own forces outside the pyramid: no feedback
        return np.array(solution["x"]).ravel()
