"""Boundary conditions of a swing (decisions 12-14).

Position and velocity at lift-off and touch-down equal the stance path's, so the foot neither
slips nor stamps. In joint space they are mapped through closed-form IK and the foot Jacobian.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from scalf_opt.locomotion.gait import Gait
from scalf_opt.locomotion.stance import stance_path
from scalf_opt.model.kinematics import LegKinematics
from scalf_opt.types import Space


@dataclass(frozen=True)
class SwingBoundary:
    """Boundary conditions of one leg's swing in one space (position, velocity in SI units).

    Attributes:
        space: ``foot`` (metres) or ``joint`` (radians).
        start: Value at lift-off, shape (2,).
        end: Value at touch-down, shape (2,).
        start_rate: Time derivative at lift-off, shape (2,) [per s].
        end_rate: Time derivative at touch-down, shape (2,) [per s].
        duration_s: Swing duration T_sw [s].
    """

    space: Space
    start: np.ndarray
    end: np.ndarray
    start_rate: np.ndarray
    end_rate: np.ndarray
    duration_s: float


def foot_boundary(gait: Gait, leg: str) -> SwingBoundary:
    """Swing boundary conditions in foot space (leg frame) of ``leg`` for ``gait``."""
    p_stance, pd_stance, _ = stance_path(gait, np.array([0.0, gait.stance_duration_s]), leg)
    return SwingBoundary(
        space="foot",
        start=p_stance[:, 1],  # lift-off = end of stance
        end=p_stance[:, 0],  # touch-down = start of stance
        start_rate=pd_stance[:, 1],
        end_rate=pd_stance[:, 0],
        duration_s=gait.swing_duration_s,
    )


def joint_boundary(gait: Gait, kin: LegKinematics) -> SwingBoundary:
    """Swing boundary conditions mapped to joint space through IK and the foot Jacobian."""
    foot = foot_boundary(gait, kin.leg.name)
    points = np.column_stack([foot.start, foot.end])
    q = kin.inverse(points)
    rates = [
        np.linalg.solve(kin.jacobian(q[:, i]), v)
        for i, v in ((0, foot.start_rate), (1, foot.end_rate))
    ]
    return SwingBoundary(
        space="joint",
        start=q[:, 0],
        end=q[:, 1],
        start_rate=rates[0],
        end_rate=rates[1],
        duration_s=foot.duration_s,
    )
