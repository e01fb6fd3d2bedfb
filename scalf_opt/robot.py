"""Load a URDF into Pinocchio once and cut out the sagittal two-joint view of one leg.

Frames (the trunk frame, which is Pinocchio's world for the fixed-base model): x forward, y left,
z up, origin at the URDF root link. The *leg frame* has the trunk's axes and its origin at the
pitching hip joint with the roll joint at zero; it moves with the trunk. Foot positions, foot
velocities and ground forces of a :class:`Leg` are expressed in the leg frame and reduced to the
sagittal plane as ``(x, z)`` pairs.

A :class:`Leg` is Pinocchio's reduced model of the robot in which every joint except the leg's
hip-pitch and knee joints is locked at zero. Both joint axes must be parallel to the trunk's y axis
(either sign); that is what makes the leg planar.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from scalf_opt.errors import ModelError

if TYPE_CHECKING:
    from scalf_opt.actuators import HydraulicCylinder
    from scalf_opt.symbolic import SymbolicChain

LEG_NAMES: tuple[str, ...] = ("RF", "LF", "RH", "LH")
"""Leg names used throughout scalf-opt: right/left, front/hind."""

AXIS_TOLERANCE = 1e-9
"""Largest |x| or |z| component a unit joint axis may have and still count as parallel to y."""


@dataclass(frozen=True)
class RobotPreset:
    """How one robot family names its legs' joints and frames.

    Attributes:
        name: Preset name (``scalf``, ``hyq``, ``solo12``).
        leg_prefix: Map from scalf-opt leg name (RF, LF, RH, LH) to the robot's own prefix.
        roll_joint: Format string of the hip roll (abduction) joint, ``{p}`` is the prefix.
        pitch_joint: Format string of the hip pitch (flexion) joint.
        knee_joint: Format string of the knee joint.
        foot_frame: Format string of the foot frame.
        stance_height_m: Default distance from the pitching hip to the ground [m] for the nominal
            standing posture.
        urdf_relpath: Where the URDF lives: relative to the repository (``scalf``) or to
            example-robot-data's ``robots`` directory.
    """

    name: str
    leg_prefix: dict[str, str]
    roll_joint: str
    pitch_joint: str
    knee_joint: str
    foot_frame: str
    stance_height_m: float
    urdf_relpath: str

    def names(self, leg: str) -> tuple[str, str, str, str]:
        """Return ``(roll_joint, pitch_joint, knee_joint, foot_frame)`` of ``leg``."""
        if leg not in self.leg_prefix:
            raise ModelError(f"unknown leg {leg!r}: choose one of {', '.join(LEG_NAMES)}")
        p = self.leg_prefix[leg]
        return (
            self.roll_joint.format(p=p),
            self.pitch_joint.format(p=p),
            self.knee_joint.format(p=p),
            self.foot_frame.format(p=p),
        )


PRESETS: dict[str, RobotPreset] = {
    "scalf": RobotPreset(
        name="scalf",
        leg_prefix={leg: leg for leg in LEG_NAMES},
        roll_joint="{p}_hip_roll",
        pitch_joint="{p}_hip_pitch",
        knee_joint="{p}_knee",
        foot_frame="{p}_foot",
        stance_height_m=0.75,
        urdf_relpath="urdf/scalf.urdf",
    ),
    "hyq": RobotPreset(
        name="hyq",
        leg_prefix={"RF": "rf", "LF": "lf", "RH": "rh", "LH": "lh"},
        roll_joint="{p}_haa_joint",
        pitch_joint="{p}_hfe_joint",
        knee_joint="{p}_kfe_joint",
        foot_frame="{p}_foot",
        stance_height_m=0.55,
        urdf_relpath="hyq_description/robots/hyq_no_sensors.urdf",
    ),
    "solo12": RobotPreset(
        name="solo12",
        leg_prefix={"RF": "FR", "LF": "FL", "RH": "HR", "LH": "HL"},
        roll_joint="{p}_HAA",
        pitch_joint="{p}_HFE",
        knee_joint="{p}_KFE",
        foot_frame="{p}_FOOT",
        stance_height_m=0.24,
        urdf_relpath="solo_description/robots/solo12.urdf",
    ),
}


def repository_root() -> Path:
    """Return the directory that holds ``urdf/`` (the repository root for an editable install)."""
    return Path(__file__).resolve().parent.parent


def default_urdf_path() -> Path:
    """Return the path of the SCalf URDF shipped with the repository."""
    return repository_root() / PRESETS["scalf"].urdf_relpath


def preset_urdf_path(preset: str) -> Path:
    """Return the URDF path of a named robot preset.

    SCalf's lives in this repository, the others come from example-robot-data.
    """
    if preset not in PRESETS:
        raise ModelError(f"unknown robot {preset!r}: choose one of {', '.join(PRESETS)}")
    if preset == "scalf":
        return default_urdf_path()
    from scalf_opt.robot_data import example_robot_data_dir

    return example_robot_data_dir() / PRESETS[preset].urdf_relpath


def _detect_preset(model: pin.Model, path: Path) -> RobotPreset:
    for preset in PRESETS.values():
        if all(model.existJointName(name) for leg in LEG_NAMES for name in preset.names(leg)[:3]):
            return preset
    raise ModelError(
        f"{path}: joint names match no known robot ({', '.join(PRESETS)}); "
        "name the legs' joints like SCalf's ({L}_hip_roll, {L}_hip_pitch, {L}_knee, {L}_foot)"
    )


@dataclass(frozen=True)
class Robot:
    """A whole robot as Pinocchio sees it (fixed base at the trunk), with named legs.

    Attributes:
        model: Pinocchio model of the whole robot, root = trunk, gravity (0, 0, -9.81) m/s^2.
        urdf_path: The URDF it was built from.
        preset: The naming convention its legs follow.
    """

    model: pin.Model
    urdf_path: Path
    preset: RobotPreset

    @classmethod
    def from_urdf(cls, urdf_path: str | Path | None = None) -> Robot:
        """Parse a URDF with Pinocchio (once) and recognise its leg naming.

        Args:
            urdf_path: Path of the URDF; default: the repository's SCalf URDF.

        Raises:
            ModelError: The file is missing, is not a URDF Pinocchio reads, or has no known legs.
        """
        path = Path(urdf_path) if urdf_path is not None else default_urdf_path()
        if not path.is_file():
            raise ModelError(f"{path}: URDF file not found")
        try:
            model = pin.buildModelFromUrdf(str(path))
        except (RuntimeError, ValueError) as exc:
            first = str(exc).strip().splitlines()[0] if str(exc).strip() else type(exc).__name__
            raise ModelError(f"{path}: not a valid URDF ({first})") from exc
        return cls(model=model, urdf_path=path, preset=_detect_preset(model, path))

    @classmethod
    def from_preset(cls, name: str) -> Robot:
        """Load a named robot: ``scalf`` (this repository), ``hyq`` or ``solo12``."""
        return cls.from_urdf(preset_urdf_path(name))

    @property
    def total_mass_kg(self) -> float:
        """Mass of the whole robot [kg]."""
        return float(sum(inertia.mass for inertia in self.model.inertias))

    @property
    def trunk_com_m(self) -> np.ndarray:
        """Centre of mass of the root link (the trunk) in the trunk frame, shape (3,) [m]."""
        # Pinocchio attaches the root link's inertia of a fixed-base model to the universe joint.
        return np.array(self.model.inertias[0].lever, dtype=float)

    @property
    def trunk_mass_kg(self) -> float:
        """Mass of the root link (the trunk) [kg]: what the stance legs carry (decision 11)."""
        return float(self.model.inertias[0].mass)

    def leg(self, name: str, actuators: dict[str, HydraulicCylinder] | None = None) -> Leg:
        """Return the sagittal two-joint view of leg ``name`` (RF, LF, RH or LH).

        Args:
            name: Leg name.
            actuators: Hydraulic cylinders keyed by joint name; the pitch and knee joints' entries
                are attached to the leg when present.
        """
        roll, pitch, knee, foot = self.preset.names(name)
        model = self.model
        for joint in (roll, pitch, knee):
            if not model.existJointName(joint):
                raise ModelError(f"{self.urdf_path}: leg {name} has no joint {joint!r}")
        if not model.existFrame(foot):
            raise ModelError(f"{self.urdf_path}: leg {name} has no foot frame {foot!r}")
        keep = {model.getJointId(pitch), model.getJointId(knee)}
        lock = [j for j in range(1, model.njoints) if j not in keep]
        reduced = pin.buildReducedModel(model, lock, pin.neutral(model))
        table = actuators or {}
        cylinders = (table.get(pitch), table.get(knee))
        return Leg(
            name=name,
            robot=self,
            model=reduced,
            joint_names=(pitch, knee),
            foot_frame=foot,
            cylinders=cylinders,
        )


def _rot_y(angle: float, v: np.ndarray) -> np.ndarray:
    """Rotate the sagittal vector ``v = (x, z)`` about +y by ``angle`` [rad]."""
    c, s = math.cos(angle), math.sin(angle)
    return np.array([c * v[0] + s * v[1], -s * v[0] + c * v[1]])


@dataclass(frozen=True)
class Leg:
    """Sagittal two-joint view of one leg: Pinocchio's reduced model plus the planar geometry.

    Joint order everywhere: ``(hip pitch, knee)``. Angles follow the URDF convention [rad].

    Attributes:
        name: RF, LF, RH or LH.
        robot: The robot the leg belongs to.
        model: Reduced Pinocchio model with nq = nv = 2; its world frame is the trunk frame.
        joint_names: URDF names of the hip-pitch and knee joints.
        foot_frame: Name of the foot frame.
        cylinders: Hydraulic cylinder of each joint, or ``None`` for an ideal actuator.
    """

    name: str
    robot: Robot
    model: pin.Model
    joint_names: tuple[str, str]
    foot_frame: str
    cylinders: tuple[HydraulicCylinder | None, HydraulicCylinder | None]

    def __post_init__(self) -> None:
        for axis_sign, joint in zip(self.axis_signs, self.joint_names, strict=True):
            if axis_sign == 0:
                raise ModelError(
                    f"{self.robot.urdf_path}: joint {joint!r} of leg {self.name} is not parallel "
                    "to the trunk's y axis; the sagittal leg model needs pitch and knee about y"
                )

    # --- geometry at q = 0, read once from Pinocchio -------------------------------------------
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
    def reach_m(self) -> tuple[float, float]:
        """Smallest and largest hip-to-foot distance in the sagittal plane [m]."""
        l1, l2 = self.thigh_length_m, self.shank_length_m
        return abs(l1 - l2), l1 + l2

    @property
    def default_stance_height_m(self) -> float:
        """Nominal distance from the pitching hip to the ground [m] (the robot preset's value)."""
        return self.robot.preset.stance_height_m

    # --- closed-form inverse kinematics: branch chosen once, against the joint limits ----------
    @cached_property
    def ik_branch(self) -> tuple[int, float, float]:
        """Knee branch and 2-pi shifts ``(branch, shift_hip_rad, shift_knee_rad)`` of the IK.

        Both knee branches are tried at the nominal standing posture (foot straight below the hip
        at :attr:`default_stance_height_m`); the one whose angles fit the joint limits is kept (the
        one with the knee closest to the middle of its range when both fit). Every later IK call
        uses the same branch, so the map from foot position to joint angles is smooth.
        """
        target = np.array([0.0, -self.default_stance_height_m])
        lo, hi = self.lower_limits_rad, self.upper_limits_rad
        best: tuple[float, tuple[int, float, float]] | None = None
        for branch in (1, -1):
            q = self._ik_raw(target, branch)
            if q is None:
                continue
            shifts = []
            for i in range(2):
                k = math.ceil((lo[i] - q[i]) / (2 * math.pi) - 1e-12)
                shift = 2 * math.pi * k
                if q[i] + shift > hi[i] + 1e-12:
                    break
                shifts.append(shift)
            if len(shifts) < 2:
                continue
            # inside the limits: among admissible 2-pi shifts take the one nearest mid-range
            for i in range(2):
                mid = 0.5 * (lo[i] + hi[i])
                while q[i] + shifts[i] + 2 * math.pi <= hi[i] and abs(
                    q[i] + shifts[i] + 2 * math.pi - mid
                ) < abs(q[i] + shifts[i] - mid):
                    shifts[i] += 2 * math.pi
            knee_mid = 0.5 * (lo[1] + hi[1])
            score = abs(q[1] + shifts[1] - knee_mid)
            if best is None or score < best[0] - 1e-12:
                best = (score, (branch, shifts[0], shifts[1]))
        if best is None:
            raise ModelError(
                f"leg {self.name}: no knee branch reaches the nominal posture (foot "
                f"{self.default_stance_height_m:.3f} m below the hip) inside the joint limits"
            )
        return best[1]

    def _ik_raw(self, p: np.ndarray, branch: int) -> np.ndarray | None:
        """Closed-form IK without 2-pi shifts (numeric, used to choose the branch)."""
        k0, f0 = self.thigh_vector_m, self.shank_vector_m
        l1, l2 = self.thigh_length_m, self.shank_length_m
        c = (p @ p - l1 * l1 - l2 * l2) / (2 * l1 * l2)
        if not -1.0 <= c <= 1.0:
            return None
        s1, s2 = self.axis_signs
        psi_k, psi_f = math.atan2(k0[0], k0[1]), math.atan2(f0[0], f0[1])
        knee = s2 * (branch * math.acos(c) - psi_f + psi_k)
        v = k0 + _rot_y(s2 * knee, f0)
        hip = s1 * math.atan2(p[0] * v[1] - p[1] * v[0], p[0] * v[0] + p[1] * v[1])
        return np.array([hip, knee])

    # --- Pinocchio dynamics (numeric) -----------------------------------------------------------
    def inverse_dynamics(self, q: np.ndarray, qd: np.ndarray, qdd: np.ndarray) -> np.ndarray:
        """Joint torques of the free leg (no contact force) [N m], ``pin.rnea``."""
        return np.array(pin.rnea(self.model, self.model.createData(), q, qd, qdd))

    def mass_matrix(self, q: np.ndarray) -> np.ndarray:
        """Joint-space mass matrix M(q) [kg m^2], ``pin.crba`` symmetrised."""
        m = np.array(pin.crba(self.model, self.model.createData(), q))
        return np.triu(m) + np.triu(m, 1).T

    def gravity_torques(self, q: np.ndarray) -> np.ndarray:
        """Generalised gravity G(q) [N m]."""
        return np.array(pin.computeGeneralizedGravity(self.model, self.model.createData(), q))

    def bias_torques(self, q: np.ndarray, qd: np.ndarray) -> np.ndarray:
        """Coriolis, centrifugal and gravity torques C(q, qd) qd + G(q) [N m]."""
        return np.array(pin.nonLinearEffects(self.model, self.model.createData(), q, qd))

    @cached_property
    def symbolic(self) -> SymbolicChain:
        """The CasADi twin of :attr:`model` (built once, lazily)."""
        from scalf_opt.symbolic import SymbolicChain

        return SymbolicChain(self.model)
