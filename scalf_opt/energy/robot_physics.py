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
from types import MappingProxyType

from scalf_opt.actuators.drive import Drive
from scalf_opt.actuators.sidecar import drives_for, leg_drives
from scalf_opt.energy.loads import StanceDistribution
from scalf_opt.energy.physics import LegPhysics
from scalf_opt.locomotion.gait import Gait
from scalf_opt.model.kinematics import LegKinematics
from scalf_opt.model.robot import Robot


class RobotPhysics:
    """A robot's legs' physics over their drives; each leg's built on first use, then kept.

    Args:
        robot: The robot.
        drives: Drives keyed by joint name; ``None`` reads the actuator file beside the URDF,
            ``{}`` gives every joint an ideal drive.
    """

    def __init__(self, robot: Robot, drives: Mapping[str, Drive] | None = None) -> None:
        self.robot = robot
        self.drives: Mapping[str, Drive] = MappingProxyType(
            dict(drives_for(robot) if drives is None else drives)
        )
        self._legs: dict[str, LegPhysics] = {}
        self.distributions: dict[tuple[Gait, str, str], StanceDistribution] = {}
        """How each gait's stance feet share a wrench (:mod:`scalf_opt.energy.loads`), kept
        across the pipelines of one gait (the optimizers make many)."""

    def leg(self, name: str) -> LegPhysics:
        """The leg's :class:`LegPhysics` (built once: the one cache of this object)."""
        if name not in self._legs:
            model_leg = self.robot.leg(name)
            self._legs[name] = LegPhysics(
                LegKinematics(model_leg), leg_drives(dict(self.drives), model_leg.joint_names)
            )
        return self._legs[name]
