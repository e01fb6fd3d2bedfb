"""A robot cycle replayed in the world: the trunk advancing at the gait's speed over a few cycles.

World frame: x forward, y left, z up, the ground at z = 0; the trunk starts at x = 0 and moves
along +x at the gait's speed, at the constant height that puts every pitching hip the stance
height above the ground (the paper's precondition b). Joint angles come from the cycle's samples
(roll joints and any other joint at Pinocchio's neutral value); every foot position is Pinocchio's
forward kinematics of those angles, so the drawn foot paths are where the animated feet go.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

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
        power_w: The leg's charged power (both joints, drive losses included), shape (n,) [W].
        swing: True where the leg is in swing (the end samples of a swing included), shape (n,).
    """

    t_s: np.ndarray
    position_m: np.ndarray
    power_w: np.ndarray
    swing: np.ndarray


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

    @cached_property
    def trunk_height_m(self) -> float:
        """Height of the trunk frame's origin above the ground [m]."""
        hips = [self.robot.leg(leg).hip_origin_m[2] for leg in self.cycle.legs]
        return float(self.cycle.gait.stance_height_m - np.mean(hips))

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
