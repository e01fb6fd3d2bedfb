"""The robot's physics, built once per URDF and actuator file: the model half of model/data.

Pinocchio keeps a robot's ``Model`` (what it is) apart from its ``Data`` (one evaluation's
buffers); Drake keeps a System apart from its Context. Here :class:`RobotPhysics` is the model
half: the robot, its drives and each leg's :class:`~scalf_opt.energy.physics.LegPhysics` (the
CasADi functions, and through them the compiled kernels the optimizers key on). It does not
depend on the gait or the accounting, so one instance serves every gait, rate and accounting
of the robot; :class:`~scalf_opt.energy.pipeline.EnergyPipeline` is the light per-gait,
per-accounting evaluation on top of it, and owns that gait's caches.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType

from scalf_opt.actuators.drive import Drive
from scalf_opt.actuators.sidecar import drives_for, leg_drives
from scalf_opt.energy.physics import LegPhysics
from scalf_opt.model.kinematics import LegKinematics
from scalf_opt.model.robot import Robot
from scalf_opt.types import LEG_NAMES


@dataclass(frozen=True)
class RobotPhysics:
    """A robot's legs' physics over their drives (build it with :meth:`build`).

    Attributes:
        robot: The robot.
        drives: Drives keyed by joint name (a joint not named has an ideal drive).
        legs: Each leg's physics, by leg name; each compiles its kernels on first use
            (:class:`~scalf_opt.energy.built_once.BuiltOnce`) and keeps them.
    """

    robot: Robot
    drives: Mapping[str, Drive]
    legs: Mapping[str, LegPhysics]

    @classmethod
    def build(cls, robot: Robot, drives: Mapping[str, Drive] | None = None) -> RobotPhysics:
        """The physics of ``robot``'s legs.

        Args:
            robot: The robot.
            drives: Drives keyed by joint name; ``None`` reads the robot's actuator file, ``{}``
                gives every joint an ideal drive.

        Raises:
            ConfigError: The actuator file is invalid or names a joint the robot lacks.
        """
        chosen = dict(drives_for(robot) if drives is None else drives)
        legs = {}
        for name in LEG_NAMES:
            leg = robot.leg(name)
            legs[name] = LegPhysics(LegKinematics(leg), leg_drives(chosen, leg.joint_names))
        return cls(robot, MappingProxyType(chosen), MappingProxyType(legs))

    def leg(self, name: str) -> LegPhysics:
        """The leg's :class:`LegPhysics`.

        Raises:
            ModelError: No such leg (the message lists the legs).
        """
        if name not in self.legs:
            self.robot.leg(name)  # raises the robot's one-line error for an unknown leg
        return self.legs[name]
