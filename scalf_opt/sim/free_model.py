"""The MuJoCo model of a robot in 3-D: the trunk free in six degrees of freedom, every joint.

The 3-D referee's robot (:mod:`scalf_opt.sim.whole_body_run`), built from the URDF by the same
edits as the sagittal model (:func:`~scalf_opt.sim.mujoco_model.urdf_spec`: no visual or collision
geometry, inertias MuJoCo refuses repaired, the joints' URDF friction and damping left out), except
that every actuated joint of the 3-D model (:class:`~scalf_opt.energy.whole_body.WholeBodyPhysics`,
abduction included) keeps its freedom and gets a torque motor, and the trunk gets a free joint.
Each foot is a sphere centred on its foot frame; only the feet touch the ground.

Pinocchio and MuJoCo write a free body's state differently: Pinocchio's ``q`` holds the position
and the quaternion ``(x, y, z, w)``, its ``v`` the linear and angular velocity in the trunk's
axes; MuJoCo's ``qpos`` holds the quaternion ``(w, x, y, z)`` and its ``qvel`` the linear velocity
in world axes and the angular velocity in the trunk's. :meth:`FreeSimModel.set_state` and
:meth:`FreeSimModel.pinocchio_state` convert, so that everything outside this module speaks
Pinocchio's convention.
"""

from __future__ import annotations

from dataclasses import dataclass

import mujoco
import numpy as np
import pinocchio as pin

from scalf_opt.energy.whole_body import WholeBodyPhysics
from scalf_opt.sim.mujoco_model import compile_spec, urdf_spec
from scalf_opt.sim.settings import SimSettings

FREE_JOINT = "trunk_free"
"""Name of the trunk's free joint in the MuJoCo model."""


@dataclass(frozen=True)
class FreeSimModel:
    """A compiled 3-D MuJoCo model and where the 3-D model's quantities live in it.

    Attributes:
        model: The compiled model (z up, gravity -9.81 m/s^2, ground plane at z = 0).
        physics: The 3-D model it mirrors (its joint and foot order is used throughout).
        free_qpos: qpos address of the free joint (7 entries from there).
        free_dof: qvel address of the free joint (6 entries from there).
        joint_qpos: qpos address of each actuated joint, in ``physics.joint_names`` order.
        joint_dof: qvel address of each, same order.
        actuators: The motor of each, same order.
        foot_geom: Each foot's sphere, in ``physics.feet`` order.
        foot_radius_m: Radius of the foot spheres [m].
        effort_limit_nm: Each joint's URDF effort limit (``inf`` where it gives none) [N m].
        repairs: What was changed so that MuJoCo takes the URDF.
    """

    model: mujoco.MjModel
    physics: WholeBodyPhysics
    free_qpos: int
    free_dof: int
    joint_qpos: np.ndarray
    joint_dof: np.ndarray
    actuators: np.ndarray
    foot_geom: np.ndarray
    foot_radius_m: float
    effort_limit_nm: np.ndarray
    repairs: tuple[str, ...]

    def set_state(self, data: mujoco.MjData, q: np.ndarray, v: np.ndarray) -> None:
        """Put ``data`` in Pinocchio's free-flyer state ``(q, v)`` (module docstring)."""
        quat_xyzw = q[3:7]
        data.qpos[self.free_qpos : self.free_qpos + 3] = q[:3]
        data.qpos[self.free_qpos + 3 : self.free_qpos + 7] = np.r_[quat_xyzw[3], quat_xyzw[:3]]
        data.qpos[self.joint_qpos] = q[7:]
        rotation = pin.Quaternion(quat_xyzw).toRotationMatrix()
        data.qvel[self.free_dof : self.free_dof + 3] = rotation @ v[:3]
        data.qvel[self.free_dof + 3 : self.free_dof + 6] = v[3:6]
        data.qvel[self.joint_dof] = v[6:]

    def pinocchio_state(self, data: mujoco.MjData) -> tuple[np.ndarray, np.ndarray]:
        """``data``'s state as Pinocchio's free-flyer ``(q, v)``."""
        wxyz = data.qpos[self.free_qpos + 3 : self.free_qpos + 7]
        quat_xyzw = np.r_[wxyz[1:], wxyz[0]] / np.linalg.norm(wxyz)
        q = np.r_[
            data.qpos[self.free_qpos : self.free_qpos + 3], quat_xyzw, data.qpos[self.joint_qpos]
        ]
        rotation = pin.Quaternion(quat_xyzw).toRotationMatrix()
        v = np.r_[
            rotation.T @ data.qvel[self.free_dof : self.free_dof + 3],
            data.qvel[self.free_dof + 3 : self.free_dof + 6],
            data.qvel[self.joint_dof],
        ]
        return q, v


def build_free_model(physics: WholeBodyPhysics, settings: SimSettings) -> FreeSimModel:
    """Build the 3-D MuJoCo model of ``physics``' robot from its URDF.

    ``settings`` must be complete (:meth:`SimSettings.for_leg_length`).

    Raises:
        ModelError: The URDF cannot be read, or MuJoCo refuses the model (the message names the
            file and gives MuJoCo's reason).
    """
    robot, pin_model = physics.robot, physics.model
    radius = settings.value("foot_radius_m")
    built = urdf_spec(robot, set(physics.joint_names), settings)
    spec = built.spec
    spec.body(built.trunk_link).add_freejoint(name=FREE_JOINT)
    for foot in physics.feet:
        frame = pin_model.frames[pin_model.getFrameId(foot)]
        link = built.child_links[pin_model.names[frame.parentJoint]]
        spec.body(link).add_geom(
            name=f"{foot}_contact",
            type=mujoco.mjtGeom.mjGEOM_SPHERE,
            size=[radius, 0, 0],
            pos=np.array(frame.placement.translation),
            contype=1,
            conaffinity=0,
            condim=3,
            friction=built.friction,
            solref=built.solref,
            mass=0.0,
        )
    for name in physics.joint_names:
        spec.add_actuator(
            name=name, target=name, trntype=mujoco.mjtTrn.mjTRN_JOINT, gear=[1, 0, 0, 0, 0, 0]
        )
    model = compile_spec(spec, robot)
    joints = [model.joint(name).id for name in physics.joint_names]
    free = model.joint(FREE_JOINT).id
    effort = np.array(pin_model.effortLimit[6:], dtype=float)
    return FreeSimModel(
        model=model,
        physics=physics,
        free_qpos=int(model.jnt_qposadr[free]),
        free_dof=int(model.jnt_dofadr[free]),
        joint_qpos=np.array([model.jnt_qposadr[j] for j in joints], dtype=int),
        joint_dof=np.array([model.jnt_dofadr[j] for j in joints], dtype=int),
        actuators=np.array([model.actuator(name).id for name in physics.joint_names], dtype=int),
        foot_geom=np.array([model.geom(f"{foot}_contact").id for foot in physics.feet], dtype=int),
        foot_radius_m=radius,
        effort_limit_nm=np.where(effort > 0, effort, np.inf),
        repairs=tuple(built.repairs),
    )
