"""The sagittal two-joint view of one leg: Pinocchio's reduced model and its planar geometry.

A :class:`Leg` is Pinocchio's reduced model of the robot in which every joint except the leg's
hip-pitch and knee joints is locked at zero. Both joint axes must be parallel to the trunk's y axis
(either sign); that is what makes the leg planar.

The *leg frame* has the trunk's axes and its origin at the pitching hip joint with the roll joint
at zero; it moves with the trunk. Foot positions, foot velocities and ground forces of a leg are
expressed in the leg frame and reduced to the sagittal plane as ``(x, z)`` pairs. Joint order
everywhere: ``(hip pitch, knee)``; angles follow the URDF convention [rad].
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np
import pinocchio as pin

from scalf_opt.errors import ModelError
from scalf_opt.model.naming import LegJoints
from scalf_opt.model.symbolic import SymbolicChain

REVOLUTE_JOINTS = ("JointModelRX", "JointModelRY", "JointModelRZ", "JointModelRevoluteUnaligned")
"""Pinocchio joint models a leg's hip pitch and knee may be (bounded revolute joints)."""

AXIS_TOLERANCE = 1e-9
"""Largest |x| or |z| component a unit joint axis may have and still count as parallel to y."""


@dataclass(frozen=True)
class Leg:
    """Geometry and limits of one leg, read once from Pinocchio's reduced model.

    Attributes:
        name: RF, LH, LF or RH.
        model: Reduced Pinocchio model with nq = nv = 2; its world frame is the trunk frame.
        joint_names: URDF names of the hip-pitch and knee joints.
        foot_frame: Name of the foot frame.
        source: The URDF the leg comes from (for messages).
        reference_q_rad: A posture the leg works around (hip pitch, knee) [rad], e.g. the robot's
            standing posture; ``None`` takes the middle of the joint ranges. It fixes the knee
            branch of the inverse kinematics.
    """

    name: str
    model: pin.Model
    joint_names: tuple[str, str]
    foot_frame: str
    source: Path
    reference_q_rad: tuple[float, float] | None = None

    @classmethod
    def from_robot_model(
        cls,
        model: pin.Model,
        name: str,
        joints: LegJoints,
        source: Path,
        reference_q: np.ndarray | None = None,
    ) -> Leg:
        """Cut leg ``name`` out of the whole robot's ``model``: lock every other joint at zero.

        Args:
            model: The whole robot.
            name: Leg name.
            joints: The leg's joint and foot names.
            source: The URDF (for messages).
            reference_q: A configuration of the whole robot (nq) whose hip-pitch and knee
                angles become the leg's reference posture; ``None``: mid-range.

        Raises:
            ModelError: A joint or the foot frame is missing, or a joint axis is not along y.
        """
        for joint in (joints.roll, joints.pitch, joints.knee):
            if joint is not None and not model.existJointName(joint):
                raise ModelError(f"{source}: leg {name} has no joint {joint!r}")
        if not model.existFrame(joints.foot):
            raise ModelError(f"{source}: leg {name} has no foot frame {joints.foot!r}")
        ids = (model.getJointId(joints.pitch), model.getJointId(joints.knee))
        for joint_id in ids:
            kind = model.joints[joint_id].shortname()
            if kind not in REVOLUTE_JOINTS:
                raise ModelError(
                    f"{source}: leg {name}: joint {model.names[joint_id]!r} is a {kind}, not a "
                    "revolute joint with limits (the sagittal leg needs revolute hip and knee)"
                )
            if model.inertias[joint_id].mass <= 0:
                raise ModelError(
                    f"{source}: leg {name}: the link moved by {model.names[joint_id]!r} has no "
                    "mass; a leg link needs a positive mass"
                )
        lock = [j for j in range(1, model.njoints) if j not in ids]
        reduced = pin.buildReducedModel(model, lock, pin.neutral(model))
        posture = None
        if reference_q is not None:
            hip, knee = (float(reference_q[model.joints[i].idx_q]) for i in ids)
            posture = (hip, knee)
        return cls(name, reduced, (joints.pitch, joints.knee), joints.foot, source, posture)

    def __post_init__(self) -> None:
        for axis_sign, joint in zip(self.axis_signs, self.joint_names, strict=True):
            if axis_sign == 0:
                raise ModelError(
                    f"{self.source}: joint {joint!r} of leg {self.name} is not parallel "
                    "to the trunk's y axis; the sagittal leg model needs pitch and knee about y"
                )

    @cached_property
    def _zero_placements(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        data = self.model.createData()
        q0 = np.zeros(self.model.nq)
        pin.forwardKinematics(self.model, data, q0)
        pin.updateFramePlacements(self.model, data)
        hip = np.array(data.oMi[1].translation)
        knee = np.array(data.oMi[2].translation)
        foot = np.array(data.oMf[self.foot_frame_id].translation)
        jacobians = pin.computeJointJacobians(self.model, data, q0)
        # The angular part of a revolute joint's column is its unit axis in the trunk frame.
        axes = np.array([jacobians[3:, i] for i in (0, 1)])
        return hip, knee, foot, axes

    @cached_property
    def foot_frame_id(self) -> int:
        """Index of the foot frame in :attr:`model`."""
        return int(self.model.getFrameId(self.foot_frame))

    @cached_property
    def hip_origin_m(self) -> np.ndarray:
        """Pitching-hip joint origin in the trunk frame, shape (3,) [m]: the leg frame's origin."""
        return self._zero_placements[0]

    @cached_property
    def axis_signs(self) -> tuple[int, int]:
        """Sign of each joint axis along the trunk's +y axis (0 when not parallel to y)."""
        signs = []
        for axis in self._zero_placements[3]:
            parallel = abs(axis[0]) < AXIS_TOLERANCE and abs(axis[2]) < AXIS_TOLERANCE
            signs.append(int(np.sign(axis[1])) if parallel else 0)
        return signs[0], signs[1]

    @cached_property
    def thigh_vector_m(self) -> np.ndarray:
        """Sagittal vector (x, z) from the hip-pitch axis to the knee axis at q = 0 [m]."""
        hip, knee, _, _ = self._zero_placements
        return np.array([knee[0] - hip[0], knee[2] - hip[2]])

    @cached_property
    def shank_vector_m(self) -> np.ndarray:
        """Sagittal vector (x, z) from the knee axis to the foot point at q = 0 [m]."""
        _, knee, foot, _ = self._zero_placements
        return np.array([foot[0] - knee[0], foot[2] - knee[2]])

    @property
    def thigh_length_m(self) -> float:
        """Sagittal distance hip axis to knee axis [m] (Table 1: l1)."""
        return float(np.linalg.norm(self.thigh_vector_m))

    @property
    def shank_length_m(self) -> float:
        """Sagittal distance knee axis to foot point [m] (Table 1: l2)."""
        return float(np.linalg.norm(self.shank_vector_m))

    @property
    def foot_lateral_m(self) -> float:
        """Foot y coordinate in the leg frame [m] (constant: the leg moves in a plane)."""
        _, _, foot, _ = self._zero_placements
        return float(foot[1] - self.hip_origin_m[1])

    @property
    def is_hind(self) -> bool:
        """Mirror flag: True for a hind leg (hip behind the trunk origin)."""
        return bool(self.hip_origin_m[0] < 0.0)

    @property
    def lower_limits_rad(self) -> np.ndarray:
        """Lower joint limits (hip pitch, knee) [rad]."""
        return np.array(self.model.lowerPositionLimit, dtype=float)

    @property
    def upper_limits_rad(self) -> np.ndarray:
        """Upper joint limits (hip pitch, knee) [rad]."""
        return np.array(self.model.upperPositionLimit, dtype=float)

    @property
    def effort_limits_nm(self) -> np.ndarray:
        """Joint effort limits [N m]."""
        return np.array(self.model.effortLimit, dtype=float)

    @property
    def velocity_limits_rad_s(self) -> np.ndarray:
        """Joint velocity limits [rad/s]."""
        return np.array(self.model.velocityLimit, dtype=float)

    @property
    def reference_posture_rad(self) -> np.ndarray:
        """The posture the leg works around (hip pitch, knee) [rad].

        The robot's given posture, else the middle of the joint ranges.
        """
        if self.reference_q_rad is not None:
            return np.array(self.reference_q_rad)
        return 0.5 * (self.lower_limits_rad + self.upper_limits_rad)

    @property
    def reach_m(self) -> tuple[float, float]:
        """Smallest and largest hip-to-foot distance in the sagittal plane [m]."""
        l1, l2 = self.thigh_length_m, self.shank_length_m
        return abs(l1 - l2), l1 + l2

    @cached_property
    def symbolic(self) -> SymbolicChain:
        """The CasADi twin of :attr:`model` (built once, lazily)."""
        return SymbolicChain(self.model)
