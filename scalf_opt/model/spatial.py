"""Spatial algebra on CasADi expressions, in Pinocchio's conventions.

A placement ``M = (R, p)`` maps child to parent coordinates. Spatial motions ``(v, w)`` and
forces ``(f, n)`` are expressed in a body frame with the linear part first.
"""

from __future__ import annotations

from typing import Any

import casadi as ca
import numpy as np

from scalf_opt.errors import ModelError
from scalf_opt.types import Expr

_AXES = {
    "X": np.array([1.0, 0.0, 0.0]),
    "Y": np.array([0.0, 1.0, 0.0]),
    "Z": np.array([0.0, 0.0, 1.0]),
}

Placement = tuple[Expr, Expr]
"""A rigid transform (R 3x3, p 3x1)."""


def joint_kind(joint: Any, name: str) -> tuple[str, np.ndarray]:
    """('revolute' | 'prismatic', unit axis in the joint frame) of a Pinocchio joint model."""
    short = joint.shortname()
    if short in ("JointModelRX", "JointModelRY", "JointModelRZ"):
        return "revolute", _AXES[short[-1]]
    if short in ("JointModelPX", "JointModelPY", "JointModelPZ"):
        return "prismatic", _AXES[short[-1]]
    if short == "JointModelRevoluteUnaligned":
        return "revolute", np.array(joint.extract().axis, dtype=float)
    if short == "JointModelPrismaticUnaligned":
        return "prismatic", np.array(joint.extract().axis, dtype=float)
    if short == "JointModelFreeFlyer":
        return "freeflyer", np.zeros(3)
    raise ModelError(
        f"joint {name!r} is a {short}: the symbolic twin supports revolute (any axis), prismatic, "
        "free-flyer and fixed joints only"
    )


def quaternion_rotation(x: Expr, y: Expr, z: Expr, w: Expr) -> Expr:
    """The rotation matrix of a unit quaternion ``(x, y, z, w)`` (Eigen's, Pinocchio's order)."""
    return ca.vertcat(
        ca.horzcat(1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)),
        ca.horzcat(2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)),
        ca.horzcat(2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)),
    )


def skew(u: Expr) -> Expr:
    """The cross-product matrix of a 3-vector."""
    return ca.vertcat(
        ca.horzcat(0, -u[2], u[1]), ca.horzcat(u[2], 0, -u[0]), ca.horzcat(-u[1], u[0], 0)
    )


def act_inv_motion(rot: Expr, pos: Expr, lin: Expr, ang: Expr) -> tuple[Expr, Expr]:
    """Express a motion given in the parent frame in the child frame of placement (rot, pos)."""
    return ca.mtimes(rot.T, lin - ca.cross(pos, ang)), ca.mtimes(rot.T, ang)


def act_force(rot: Expr, pos: Expr, lin: Expr, ang: Expr) -> tuple[Expr, Expr]:
    """Express a force given in the child frame in the parent frame of placement (rot, pos)."""
    f = ca.mtimes(rot, lin)
    return f, ca.mtimes(rot, ang) + ca.cross(pos, f)
