r"""The whole robot in 3-D: a floating trunk, every actuated joint, point feet, every joint's drive.

:class:`WholeBodyPhysics` is the 3-D model's counterpart of the sagittal
:class:`~scalf_opt.energy.robot_physics.RobotPhysics`: built once per robot, immutable, and the one
place where the 3-D motion's loads and power are written down (as CasADi expressions evaluated
numerically through the same functions).

Coordinates. The optimizer's generalised coordinates are

.. math::

    X = (p_x, p_y, p_z, \phi, \theta, \psi, q_1 \dots q_n),

the trunk's (root link's) position in the world [m], its roll, pitch and yaw [rad] (``R = R_z(\psi)
R_y(\theta) R_x(\phi)``, never near the pitch singularity on a walking robot) and the actuated
joints' angles in Pinocchio's order [rad]. Pinocchio's free-flyer state follows from
``(X, Xd, Xdd)`` (:meth:`WholeBodyPhysics.pinocchio_state`): ``q = (p, quaternion(x, y, z, w),
q_j)``, ``v = (R^T \dot p, \omega_b, \dot q_j)`` and ``a = \dot v`` (Pinocchio's free-flyer
acceleration is the time derivative of the base-frame velocity: ``a_lin = R^T \ddot p - \omega_b
\times R^T \dot p``), with ``\omega_b = E(\phi, \theta) (\dot\phi, \dot\theta, \dot\psi)`` the
body-frame angular velocity.

Loads. With the stance feet's forces ``f_k`` (world axes, on the robot) the floating-base inverse
dynamics ``RNEA(q, v, a) - \sum_k J_k^T f_k`` (:meth:`~scalf_opt.model.symbolic.SymbolicChain.
contact_rnea`) has the base's wrench in its first six rows, zero when the forces carry the robot,
and the joint torques in the others.

Drives. Every actuated joint has a drive: the actuator file's where it names the joint; for a joint
it does not name (the abduction joints: the actuator files describe the sagittal joints), the same
leg's hip-pitch drive when that is an electric drive (the legged robots in the catalog use one
motor type at the hip: an estimate, stated in every record), else an ideal drive (its mechanical
power under the accounting, no losses).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property
from typing import Any

import casadi as ca
import numpy as np
import pinocchio as pin

from scalf_opt.actuators.drive import Drive, IdealDrive
from scalf_opt.actuators.electric import ElectricDrive
from scalf_opt.actuators.sidecar import drives_for
from scalf_opt.actuators.stribeck import smooth_max
from scalf_opt.energy.accounting import accounting as power_accounting
from scalf_opt.energy.box_bound import Bound
from scalf_opt.energy.built_once import BuiltOnce
from scalf_opt.errors import ModelError
from scalf_opt.model.robot import Robot
from scalf_opt.model.symbolic import SymbolicChain
from scalf_opt.model.urdf_file import read_urdf_text
from scalf_opt.types import LEG_NAMES, Accounting

BASE_COORDINATES = ("base_x", "base_y", "base_z", "base_roll", "base_pitch", "base_yaw")
"""Names of the trunk's six coordinates in ``X`` (metres, then radians)."""

DRIVE_FROM_FILE = "actuator file"
DRIVE_FROM_HIP = "estimate: the leg's hip-pitch drive"
DRIVE_IDEAL = "ideal: no drive named in the actuator file"


def rpy_rotation(rpy: ca.SX) -> ca.SX:
    """``R_z(yaw) R_y(pitch) R_x(roll)`` (3x3) of roll, pitch, yaw [rad]."""
    cr, sr = ca.cos(rpy[0]), ca.sin(rpy[0])
    cp, sp = ca.cos(rpy[1]), ca.sin(rpy[1])
    cy, sy = ca.cos(rpy[2]), ca.sin(rpy[2])
    return ca.vertcat(
        ca.horzcat(cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr),
        ca.horzcat(sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr),
        ca.horzcat(-sp, cp * sr, cp * cr),
    )


def rpy_quaternion(rpy: ca.SX) -> ca.SX:
    """Unit quaternion ``(x, y, z, w)`` of the rotation :func:`rpy_rotation`."""
    cr, sr = ca.cos(rpy[0] / 2), ca.sin(rpy[0] / 2)
    cp, sp = ca.cos(rpy[1] / 2), ca.sin(rpy[1] / 2)
    cy, sy = ca.cos(rpy[2] / 2), ca.sin(rpy[2] / 2)
    return ca.vertcat(
        sr * cp * cy - cr * sp * sy,
        cr * sp * cy + sr * cp * sy,
        cr * cp * sy - sr * sp * cy,
        cr * cp * cy + sr * sp * sy,
    )


def quaternion_rpy(quat_xyzw: np.ndarray) -> np.ndarray:
    """Roll, pitch, yaw [rad] (3, n) of quaternions ``(x, y, z, w)`` (4, n), numeric.

    The inverse of :func:`rpy_quaternion` for pitch inside +-90 deg (normalised first):
    ``R_20 = -sin(pitch)``, ``R_21 = cos(pitch) sin(roll)``, ``R_22 = cos(pitch) cos(roll)``,
    ``R_10 / R_00 = tan(yaw)``.
    """
    qx, qy, qz, qw = quat_xyzw / np.linalg.norm(quat_xyzw, axis=0)
    r00, r10 = 1 - 2 * (qy**2 + qz**2), 2 * (qx * qy + qw * qz)
    r20, r21, r22 = 2 * (qx * qz - qw * qy), 2 * (qy * qz + qw * qx), 1 - 2 * (qx**2 + qy**2)
    return np.vstack(
        [np.arctan2(r21, r22), np.arctan2(-r20, np.hypot(r21, r22)), np.arctan2(r10, r00)]
    )


def body_angular_velocity(rpy: ca.SX, rpy_dot: ca.SX) -> ca.SX:
    """The trunk's angular velocity in its own axes [rad/s] from the roll-pitch-yaw rates."""
    cr, sr = ca.cos(rpy[0]), ca.sin(rpy[0])
    cp, sp = ca.cos(rpy[1]), ca.sin(rpy[1])
    return ca.vertcat(
        rpy_dot[0] - sp * rpy_dot[2],
        cr * rpy_dot[1] + sr * cp * rpy_dot[2],
        -sr * rpy_dot[1] + cr * cp * rpy_dot[2],
    )


def free_flyer_model(robot: Robot) -> pin.Model:
    """Pinocchio's model of ``robot`` with a free-flyer root (its trunk free in 6 DoF).

    Raises:
        ModelError: A joint is not a one-degree-of-freedom joint with one coordinate (a
            continuous joint's two coordinates have no place in ``X``).
    """
    model = pin.buildModelFromXML(read_urdf_text(robot.urdf_path), pin.JointModelFreeFlyer())
    if model.nq - 7 != model.nv - 6:
        raise ModelError(
            f"{robot.urdf_path}: the 3-D model needs joints of one coordinate each "
            f"(nq = {model.nq}, nv = {model.nv}: a continuous joint?)"
        )
    return model


@dataclass(frozen=True)
class WholeBodyPhysics:
    """The 3-D whole-body model of one robot: free-flyer dynamics, feet, drives (immutable).

    Attributes:
        robot: The robot (its fixed-base model names the legs).
        model: Pinocchio's free-flyer model of the same URDF.
        feet: Foot frame of each leg, in :data:`~scalf_opt.types.LEG_NAMES` order.
        joint_names: The actuated joints in Pinocchio's order (the columns of ``X`` after six).
        drives: Each joint's drive, in that order.
        drive_origins: Where each drive comes from (:data:`DRIVE_FROM_FILE`, ...).
        joint_legs: The leg (index into :data:`LEG_NAMES`) each joint moves.
    """

    robot: Robot
    model: pin.Model
    feet: tuple[str, ...]
    joint_names: tuple[str, ...]
    drives: tuple[Drive, ...]
    drive_origins: tuple[str, ...]
    joint_legs: tuple[int, ...]

    @classmethod
    def of(cls, robot: Robot) -> WholeBodyPhysics:
        """Build the 3-D model of ``robot`` (reads the URDF and the actuator file once)."""
        model = free_flyer_model(robot)
        names = tuple(model.names[i] for i in range(2, model.njoints))
        feet = tuple(robot.leg(leg).foot_frame for leg in LEG_NAMES)
        known = drives_for(robot)
        legs = _joint_legs(model, feet, names)
        drives: list[Drive] = []
        origins: list[str] = []
        for name, leg in zip(names, legs, strict=True):
            if name in known:
                drives.append(known[name])
                origins.append(DRIVE_FROM_FILE)
                continue
            hip = known.get(robot.leg(LEG_NAMES[leg]).joint_names[0])
            if isinstance(hip, ElectricDrive):
                drives.append(replace(hip, joint_name=name))
                origins.append(DRIVE_FROM_HIP)
            else:
                drives.append(IdealDrive(joint_name=name))
                origins.append(DRIVE_IDEAL)
        return cls(robot, model, feet, names, tuple(drives), tuple(origins), legs)

    # --- sizes and data --------------------------------------------------------------------------
    @property
    def n_joints(self) -> int:
        """Number of actuated joints."""
        return len(self.joint_names)

    @property
    def nx(self) -> int:
        """Length of ``X``: six trunk coordinates and the joints."""
        return 6 + self.n_joints

    @cached_property
    def mass_kg(self) -> float:
        """The whole robot's mass [kg]."""
        return float(sum(inertia.mass for inertia in self.model.inertias))

    @property
    def weight_n(self) -> float:
        """The whole robot's weight [N] (Pinocchio's gravity)."""
        return self.mass_kg * float(np.linalg.norm(self.model.gravity.linear))

    def stride_shift(self, stride_m: float) -> np.ndarray:
        """What one cycle adds to ``X`` (nx, 1): ``stride_m`` on the trunk's x, zero elsewhere."""
        out = np.zeros((self.nx, 1))
        out[0, 0] = stride_m
        return out

    @cached_property
    def twin(self) -> SymbolicChain:
        """The CasADi twin of :attr:`model`."""
        return SymbolicChain(self.model)

    def joint_bounds(self) -> tuple[Bound, ...]:
        """Every limit of every joint: range, URDF velocity and effort limits, drive bounds.

        ``Bound.joint`` indexes :attr:`joint_names`; ``Bound.output`` is ``q``, ``qd``, ``tau`` or a
        drive channel's name (``row`` then ``None``).
        """
        model = self.model
        out: list[Bound] = []
        for j, drive in enumerate(self.drives):
            lo, hi = float(model.lowerPositionLimit[7 + j]), float(model.upperPositionLimit[7 + j])
            out.append(Bound("q", j, j, lo, hi, "joint range (URDF)", "rad"))
            velocity, effort = model.velocityLimit[6 + j], model.effortLimit[6 + j]
            if np.isfinite(velocity) and velocity > 0:
                out.append(Bound("qd", j, j, -velocity, velocity, "URDF velocity limit", "rad_s"))
            if np.isfinite(effort) and effort > 0:
                out.append(Bound("tau", j, j, -effort, effort, "URDF effort limit", "nm"))
            channels = {c.name: c.unit for c in drive.channels}
            for name, (b_lo, b_hi) in drive.output_bounds(lo, hi).items():
                source = f"{drive.kind} {name} limit (actuator file)"
                out.append(Bound(name, None, j, b_lo, b_hi, source, channels[name]))
        return tuple(out)

    # --- the coordinates' map to Pinocchio -------------------------------------------------------
    @cached_property
    def pinocchio_state_function(self) -> ca.Function:
        """``(X, Xd, Xdd) -> (q, v, a)``: Pinocchio's free-flyer state of the coordinates."""
        nx = self.nx
        x, xd, xdd = (ca.SX.sym(n, nx) for n in ("X", "Xd", "Xdd"))
        rpy, rpy_dot = x[3:6], xd[3:6]
        rot = rpy_rotation(rpy)
        omega = body_angular_velocity(rpy, rpy_dot)
        omega_dot = ca.jtimes(omega, ca.vertcat(rpy, rpy_dot), ca.vertcat(rpy_dot, xdd[3:6]))
        v_lin = ca.mtimes(rot.T, xd[:3])
        a_lin = ca.mtimes(rot.T, xdd[:3]) - ca.cross(omega, v_lin)
        q = ca.vertcat(x[:3], rpy_quaternion(rpy), x[6:])
        v = ca.vertcat(v_lin, omega, xd[6:])
        a = ca.vertcat(a_lin, omega_dot, xdd[6:])
        return ca.Function(
            "pinocchio_state", [x, xd, xdd], [q, v, a], ["X", "Xd", "Xdd"], ["q", "v", "a"]
        )

    def pinocchio_state(
        self, x: np.ndarray, xd: np.ndarray, xdd: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Pinocchio's ``(q, v, a)`` of one instant's coordinates (numeric, 1-D arrays)."""
        q, v, a = self.pinocchio_state_function(x, xd, xdd)
        return (np.array(q).ravel(), np.array(v).ravel(), np.array(a).ravel())

    @cached_property
    def feet_function(self) -> ca.Function:
        """``X -> feet_pos``: the four feet's world positions (3 x 4) [m]."""
        x = ca.SX.sym("X", self.nx)
        q = self.pinocchio_state_function(x, ca.DM.zeros(self.nx), ca.DM.zeros(self.nx))[0]
        feet = ca.horzcat(*(self.twin.frame_position(q, foot) for foot in self.feet))
        return ca.Function("feet", [x], [feet], ["X"], ["feet_pos"])

    # --- the per-instant function the NLP and the reports share ----------------------------------
    def node_function(self, accounting: Accounting, heat_eps: float | None = None) -> ca.Function:
        """One instant's loads and power: ``(X, Xd, Xdd, f) -> outputs``.

        ``f`` stacks the four feet's forces on the robot (world axes, :attr:`feet` order, 12) [N].
        Outputs: ``base_wrench`` (6: force [N] and moment [N m] in the trunk's axes about its
        origin; zero when ``f`` carries the robot), ``tau`` (joint torques [N m]), ``feet_pos`` and
        ``feet_vel`` (3 x 4, world), ``p_joint`` (signed ``tau qd`` [W]), ``charged`` (each joint's
        drawn power [W]: its charged joint power, exact, plus its drive's loss; with ``heat_eps``
        the losses smoothed as in the sagittal NLP), ``loss`` (the losses alone [W]) and each
        drive channel (``<channel>_<j>`` for joint ``j``).
        """
        return self._node_functions(accounting, heat_eps)

    def _node_functions(self, accounting: Accounting, heat_eps: float | None) -> ca.Function:
        key = (accounting, heat_eps)
        cache = self._cache
        if key not in cache:
            cache[key] = self._build_node_function(accounting, heat_eps)
        return cache[key]

    @cached_property
    def _cache(self) -> dict[tuple[Accounting, float | None], ca.Function]:
        return {}

    @cached_property
    def built(self) -> BuiltOnce:
        """What the optimizers build from this model once (its compiled point functions)."""
        return BuiltOnce()

    def _build_node_function(self, accounting: Accounting, heat_eps: float | None) -> ca.Function:
        nx = self.nx
        x, xd, xdd = (ca.SX.sym(n, nx) for n in ("X", "Xd", "Xdd"))
        forces = ca.SX.sym("f", 3 * len(self.feet))
        q, v, a = self.pinocchio_state_function(x, xd, xdd)
        out = self.twin.contact_rnea(self.feet)(q, v, a, forces)
        tau = out[6:]
        positions, velocities = [], []
        for foot in self.feet:
            positions.append(self.twin.frame_position(q, foot))
            velocities.append(ca.mtimes(self.twin.frame_jacobian(q, foot)[:3, :], v))
        p_joint, charged, loss, channels = self._drive_expressions(x, xd, tau, accounting, heat_eps)
        names = ["base_wrench", "tau", "feet_pos", "feet_vel", "p_joint", "charged", "loss"]
        values = [
            out[:6],
            tau,
            ca.horzcat(*positions),
            ca.horzcat(*velocities),
            p_joint,
            charged,
            loss,
        ]
        return ca.Function(
            f"whole_body_{accounting}",
            [x, xd, xdd, forces],
            values + list(channels.values()),
            ["X", "Xd", "Xdd", "f"],
            names + list(channels),
        )

    def _drive_expressions(
        self, x: ca.SX, xd: ca.SX, tau: ca.SX, accounting: Accounting, heat_eps: float | None
    ) -> tuple[Any, Any, Any, dict[str, Any]]:
        """Signed joint powers, drawn powers, losses [W] and drive channels of every joint."""
        charge = power_accounting(accounting).charge
        max_fn = ca.fmax if heat_eps is None else (lambda y, _: smooth_max(y, heat_eps))
        p_joint, charged, loss, channels = [], [], [], {}
        for j, drive in enumerate(self.drives):
            qj, qdj, tj = x[6 + j], xd[6 + j], tau[j]
            p = tj * qdj
            lost = drive.loss_rate(qj, qdj, tj, max_fn)
            p_joint.append(p)
            loss.append(lost)
            charged.append((charge(p) if drive.charges_joint_power else 0.0 * p) + lost)
            for name, value in drive.outputs(qj, qdj, tj).items():
                channels[f"{name}_{j}"] = value
        return ca.vertcat(*p_joint), ca.vertcat(*charged), ca.vertcat(*loss), channels

    def power_function(self, accounting: Accounting) -> ca.Function:
        """``(X, Xd, tau) -> charged``: each joint's drawn power [W] (exact), for any torques.

        What charges a plan's joints at the nodes (:meth:`node_function`) and torques computed
        elsewhere (Pinocchio's, a simulation's) alike.
        """
        key = (f"power {accounting}", None)
        if key not in self._cache:
            x, xd = ca.SX.sym("X", self.nx), ca.SX.sym("Xd", self.nx)
            tau = ca.SX.sym("tau", self.n_joints)
            charged = self._drive_expressions(x, xd, tau, accounting, None)[1]
            self._cache[key] = ca.Function(
                f"whole_body_power_{accounting}",
                [x, xd, tau],
                [charged],
                ["X", "Xd", "tau"],
                ["charged"],
            )
        return self._cache[key]

    def coordinate_names(self) -> tuple[str, ...]:
        """Names of ``X``'s entries: :data:`BASE_COORDINATES`, then the joints."""
        return BASE_COORDINATES + self.joint_names


def _joint_legs(model: pin.Model, feet: tuple[str, ...], names: tuple[str, ...]) -> tuple[int, ...]:
    """The leg each actuated joint moves: the foot whose chain it is on.

    Raises:
        ModelError: A joint moves no foot or several (a spine joint; the 3-D model has legs only).
    """
    chains = []
    for foot in feet:
        joint = model.frames[model.getFrameId(foot)].parentJoint
        chain = set()
        while joint > 1:
            chain.add(joint)
            joint = model.parents[joint]
        chains.append(chain)
    legs = []
    for i, name in enumerate(names, start=2):
        owners = [k for k, chain in enumerate(chains) if i in chain]
        if len(owners) != 1:
            raise ModelError(f"joint {name!r} moves {len(owners)} feet; the 3-D model needs legs")
        legs.append(owners[0])
    return tuple(legs)
