"""A robot cycle replayed in the world: the trunk advancing at the gait's speed over a few cycles.

:class:`Walker` is what the 3-D scene (:mod:`scalf_opt.viz.scene`) animates: the trunk's world pose
and the joints at any time, and the feet's paths. :class:`Walk` is the sagittal cycle's walker;
:class:`~scalf_opt.viz.whole_body_walk.WholeBodyWalk` the 3-D whole-body plan's.

Sagittal walk. World frame: x forward, y left, z up, the ground at z = 0; the trunk starts at
x = 0 and moves along +x at the gait's speed, at the constant height that puts every pitching hip
the stance height above the ground (the paper's precondition b). Joint angles come from the
cycle's samples (roll joints and any other joint at Pinocchio's neutral value); every foot
position is Pinocchio's forward kinematics of those angles, so the drawn foot paths are where the
animated feet go.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Protocol

import numpy as np
import pinocchio as pin

from scalf_opt.energy.cycle import LegCycle, RobotCycle
from scalf_opt.model.robot import Robot


@dataclass(frozen=True)
class FootPath:
    """One leg's foot over the whole walk, at the cycle's samples.

    Attributes:
        t_s: Time since the walk began, increasing, shape (n,) [s].
        position_m: Foot position in the world, shape (n, 3) [m].
        power_w: The leg's charged power (all its joints: hip pitch and knee in a sagittal walk;
            drive losses included), shape (n,) [W].
        swing: True where the leg is in swing (the end samples of a swing included), shape (n,).
    """

    t_s: np.ndarray
    position_m: np.ndarray
    power_w: np.ndarray
    swing: np.ndarray


class Walker(Protocol):
    """A robot walking in the world (x forward, y left, z up, the ground at z = 0), for the scene.

    The scene poses every visual at ``trunk_pose(t) @ oMi(configurations(t))`` (Pinocchio's
    forward kinematics of ``robot.model``, whose root is the trunk frame); ``foot_paths`` must be
    the feet of the same poses, so that the drawn paths are where the animated feet go.
    """

    @property
    def robot(self) -> Robot:
        """The robot walking."""
        ...

    @property
    def lateral_offset_m(self) -> float:
        """Where the trunk walks along y [m] (robots side by side)."""
        ...

    @property
    def duration_s(self) -> float:
        """Length of the walk [s] (the animation loops over it)."""
        ...

    @property
    def x_range_m(self) -> tuple[float, float]:
        """The trunk frame's world x at the walk's start and end [m]."""
        ...

    @property
    def trunk_height_m(self) -> float:
        """The trunk frame's (mean) height above the ground [m]."""
        ...

    @property
    def stance_height_m(self) -> float:
        """The pitching hips' (mean) height above the ground [m] (sizes the path tubes)."""
        ...

    def trunk_pose(self, t_s: np.ndarray) -> np.ndarray:
        """World from trunk frame at walk times ``t_s``: homogeneous, shape (n, 4, 4) [m]."""
        ...

    def configurations(self, t_s: np.ndarray) -> np.ndarray:
        """``robot.model``'s configuration at walk times ``t_s``, shape (n, nq) [rad, m]."""
        ...

    def foot_paths(self) -> dict[str, FootPath]:
        """Every leg's foot over the walk (world frame)."""
        ...


@dataclass(frozen=True)
class Walk:
    """The robot walking a cycle ``n_cycles`` times.

    Attributes:
        robot: The robot.
        cycle: The cycle walked.
        n_cycles: Number of cycles.
        lateral_offset_m: Where the trunk walks along y [m] (to set robots side by side).
    """

    robot: Robot
    cycle: RobotCycle
    n_cycles: int = 3
    lateral_offset_m: float = 0.0

    @property
    def duration_s(self) -> float:
        """Length of the walk [s]."""
        return self.n_cycles * self.cycle.gait.period_s

    @property
    def x_range_m(self) -> tuple[float, float]:
        """The trunk's world x at the walk's start and end [m] (it starts at x = 0)."""
        return 0.0, self.n_cycles * self.cycle.gait.distance_per_cycle_m

    @property
    def stance_height_m(self) -> float:
        """The gait's stance height: the pitching hips' height above the ground [m]."""
        return self.cycle.gait.stance_height_m

    @cached_property
    def trunk_height_m(self) -> float:
        """Height of the trunk frame's origin above the ground [m]."""
        hips = [self.robot.leg(leg).hip_origin_m[2] for leg in self.cycle.legs]
        return float(self.cycle.gait.stance_height_m - np.mean(hips))

    def trunk_pose(self, t_s: np.ndarray) -> np.ndarray:
        """World from trunk frame at times ``t_s`` (level: no rotation), shape (n, 4, 4) [m]."""
        position = self.trunk_position_m(t_s)
        out = np.tile(np.eye(4), (position.shape[0], 1, 1))
        out[:, :3, 3] = position
        return out

    def trunk_position_m(self, t_s: np.ndarray) -> np.ndarray:
        """World position of the trunk frame's origin at times ``t_s``, shape (n, 3) [m]."""
        t = np.atleast_1d(np.asarray(t_s, dtype=float))
        out = np.empty((t.size, 3))
        out[:, 0] = self.cycle.gait.speed_m_s * t
        out[:, 1] = self.lateral_offset_m
        out[:, 2] = self.trunk_height_m
        return out

    @cached_property
    def _joint_index(self) -> dict[str, tuple[int, int]]:
        model = self.robot.model
        out = {}
        for leg in self.cycle.legs:
            hip, knee = self.robot.leg(leg).joint_names
            out[leg] = (
                model.joints[model.getJointId(hip)].idx_q,
                model.joints[model.getJointId(knee)].idx_q,
            )
        return out

    def configurations(self, t_s: np.ndarray) -> np.ndarray:
        """The whole robot's configuration at walk times ``t_s``, shape (n, nq).

        Each leg's hip-pitch and knee angles are interpolated linearly between the cycle's
        samples (periodic in the gait period); every other joint is at its neutral value.
        """
        t = np.atleast_1d(np.asarray(t_s, dtype=float))
        period = self.cycle.gait.period_s
        q = np.tile(pin.neutral(self.robot.model), (t.size, 1))
        for leg, leg_cycle in self.cycle.legs.items():
            times, angles = _periodic_samples(leg_cycle, period)
            for row, index in enumerate(self._joint_index[leg]):
                q[:, index] = np.interp(np.mod(t, period), times, angles[row])
        return q

    def foot_paths(self) -> dict[str, FootPath]:
        """Every leg's foot over the walk, at the cycle's own samples."""
        model = self.robot.model
        data = model.createData()
        period = self.cycle.gait.period_s
        out = {}
        for leg, leg_cycle in self.cycle.legs.items():
            frame = model.getFrameId(self.robot.leg(leg).foot_frame)
            t_cycle, q_leg, power, swing = [], [], [], []
            for phase in (leg_cycle.stance, leg_cycle.swing):
                t_cycle.append(phase.t_s)
                q_leg.append(phase.values["q"])
                power.append(phase.values["power"].sum(axis=0))
                swing.append(np.full(phase.t_s.size, phase.phase == "swing"))
            t1 = np.concatenate(t_cycle)
            order = np.argsort(t1, kind="stable")
            t1, power1 = t1[order], np.concatenate(power)[order]
            q1, swing1 = np.concatenate(q_leg, axis=1)[:, order], np.concatenate(swing)[order]
            base = pin.neutral(model)
            feet = np.empty((t1.size, 3))
            hip_index, knee_index = self._joint_index[leg]
            for k in range(t1.size):
                base[hip_index], base[knee_index] = q1[0, k], q1[1, k]
                pin.framesForwardKinematics(model, data, base)
                feet[k] = data.oMf[frame].translation
            times = np.concatenate([t1 + c * period for c in range(self.n_cycles)])
            position = np.tile(feet, (self.n_cycles, 1)) + self.trunk_position_m(times)
            out[leg] = FootPath(
                t_s=times,
                position_m=position,
                power_w=np.tile(power1, self.n_cycles),
                swing=np.tile(swing1, self.n_cycles),
            )
        return out


def _periodic_samples(leg: LegCycle, period_s: float) -> tuple[np.ndarray, np.ndarray]:
    """Cycle times in [0, T] (increasing, unique) and the joint angles there, (2, n) [rad]."""
    t = np.concatenate([leg.stance.t_s, leg.swing.t_s])
    q = np.concatenate([leg.stance.values["q"], leg.swing.values["q"]], axis=1)
    order = np.argsort(t, kind="stable")
    t, q = t[order], q[:, order]
    t, first = np.unique(t, return_index=True)
    q = q[:, first]
    if t[0] > 0.0:  # close the period so that np.interp never extrapolates
        t, q = np.concatenate([[t[-1] - period_s], t]), np.concatenate([q[:, -1:], q], axis=1)
    if t[-1] < period_s:
        t, q = np.concatenate([t, [t[0] + period_s]]), np.concatenate([q, q[:, :1]], axis=1)
    return t, q
