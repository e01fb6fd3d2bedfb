"""Refuse a path that leaves a leg's reach or joint limits, naming what is wrong."""

from __future__ import annotations

import numpy as np

from scalf_opt.errors import GaitError, InfeasibleError
from scalf_opt.locomotion.gait import Gait
from scalf_opt.model.kinematics import LegKinematics
from scalf_opt.types import Phase, Space

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
            f"leg {leg.name}: the {phase} path takes joint {leg.joint_names[i]} to "
            f"{q[i, j]:.4f} rad, outside its limits "
            f"[{leg.lower_limits_rad[i]:.4f}, {leg.upper_limits_rad[i]:.4f}] rad"
        )


def check_workspace(
    kin: LegKinematics, gait: Gait, space: Space, path: np.ndarray, phase: Phase
) -> None:
    """Refuse a path that leaves the leg's reach or joint limits.

    Raises:
        GaitError: In stance: the gait itself is impossible for this leg (names the fields).
        InfeasibleError: In swing.
    """
    try:
        check_joint_limits(kin, joint_angles(kin, space, path), phase)
    except InfeasibleError as exc:
        if phase == "swing":
            raise
        offsets = ""
        if gait.stance_x_offset_front_m or gait.stance_x_offset_hind_m:
            offsets = (
                f", stance_x_offset_front_m = {gait.stance_x_offset_front_m:g}, "
                f"stance_x_offset_hind_m = {gait.stance_x_offset_hind_m:g}"
            )
        raise GaitError(
            f"gait fields stance_height_m = {gait.stance_height_m:g} and step_length_m = "
            f"{gait.step_length_m:g}{offsets} are impossible for this robot: {exc}"
        ) from exc
