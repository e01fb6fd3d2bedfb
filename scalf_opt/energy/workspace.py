"""Refuse a path that leaves a leg's reach or joint limits, naming what is wrong."""

from __future__ import annotations

import numpy as np

from scalf_opt.errors import GaitError, InfeasibleError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.model.kinematics import LegKinematics
from scalf_opt.types import JOINT_ROLES, Phase, Space

JOINT_LIMIT_TOLERANCE_RAD = 1e-9
"""Round-off allowed beyond a joint limit before a motion counts as violating it."""


def joint_angles(kin: LegKinematics, space: Space, path: np.ndarray) -> np.ndarray:
    """Joint angles (2, n) [rad] of a path's samples (3, 2, n); IK for a foot path.

    Raises:
        InfeasibleError: A foot target is out of reach.
    """
    return kin.inverse(path[0]) if space == "foot" else path[0]


def check_joint_limits(kin: LegKinematics, q: np.ndarray, phase: Phase) -> None:
    """Raise :class:`InfeasibleError` naming the first sample outside the joint limits."""
    leg = kin.leg
    lo = leg.lower_limits_rad[:, None] - JOINT_LIMIT_TOLERANCE_RAD
    hi = leg.upper_limits_rad[:, None] + JOINT_LIMIT_TOLERANCE_RAD
    bad = np.argwhere((q < lo) | (q > hi))
    if bad.size:
        i, j = bad[0]
        raise InfeasibleError(
            f"leg {leg.name}: the {phase} path takes joint {leg.joint_names[i]} "
            f"(q_{JOINT_ROLES[i]}) to "
            f"{q[i, j]:.4f} rad, outside its limits "
            f"[{leg.lower_limits_rad[i]:.4f}, {leg.upper_limits_rad[i]:.4f}] rad"
        )


def check_workspace(
    kin: LegKinematics,
    gait: Gait,
    space: Space,
    path: np.ndarray,
    phase: Phase,
    gait_fields: tuple[str, ...] = (),
) -> None:
    """Refuse a path that leaves the leg's reach or joint limits.

    Args:
        kin: The leg's kinematics.
        gait: The gait.
        space: What ``path`` holds.
        path: Samples (3, 2, n).
        phase: The phase, for the message.
        gait_fields: The gait fields that alone decide this path (the stance, the reference
            swing): a path out of the workspace is then the gait's fault and the error names them.

    Raises:
        GaitError: The path is the gait's (``gait_fields``): the gait is impossible for the leg.
        InfeasibleError: Otherwise (a swing family's member).
    """
    try:
        check_joint_limits(kin, joint_angles(kin, space, path), phase)
    except InfeasibleError as exc:
        if not gait_fields:
            raise
        names = list(gait_fields)
        if gait.stance_x_offset_front_m or gait.stance_x_offset_hind_m:
            names += ["stance_x_offset_front_m", "stance_x_offset_hind_m"]
        values = ", ".join(f"{f} = {getattr(gait, f):g}" for f in names)
        raise GaitError(
            f"gait fields {values} are impossible for this robot: {exc}", field=gait_fields[0]
        ) from exc
