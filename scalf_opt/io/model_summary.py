"""What ``scalf-opt model`` reports, as plain data.

A leg as Pinocchio sees it, its drives and a standing posture (SI units; the text report and
``--json`` both come from here).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import pinocchio as pin

from scalf_opt.actuators.drive import Drive
from scalf_opt.model.kinematics import LegKinematics
from scalf_opt.model.leg import Leg
from scalf_opt.model.robot import Robot
from scalf_opt.types import JOINT_ROLES


def _sagittal_angle(link: np.ndarray, vec: np.ndarray) -> float:
    """Signed angle about +y from sagittal vector ``link`` to ``vec`` (both (x, z)) [rad]."""
    w_link = complex(link[1], link[0])
    w_vec = complex(vec[1], vec[0])
    return math.atan2((w_vec / w_link).imag, (w_vec / w_link).real)


def leg_link_table(leg: Leg) -> list[dict[str, float]]:
    """Mass, length, COM distance and angle, inertia about the COM of the thigh and shank."""
    model = leg.model
    data = model.createData()
    pin.forwardKinematics(model, data, np.zeros(model.nq))
    rows = []
    for i, link in ((1, leg.thigh_vector_m), (2, leg.shank_vector_m)):
        inertia = model.inertias[i]
        rot = data.oMi[i].rotation
        com = rot @ inertia.lever
        com_xz = np.array([com[0], com[2]])
        rows.append(
            {
                "mass_kg": float(inertia.mass),
                "length_m": float(np.linalg.norm(link)),
                "com_distance_m": float(np.linalg.norm(com_xz)),
                "com_angle_rad": _sagittal_angle(link, com_xz),
                "inertia_yy_kg_m2": float((rot @ inertia.inertia @ rot.T)[1, 1]),
            }
        )
    return rows


def drive_summary(drive: Drive, lower_rad: float, upper_rad: float) -> dict[str, Any]:
    """A drive's kind and, for a cylinder, its geometry and its length over the joint range."""
    out: dict[str, Any] = {
        "joint": drive.joint_name,
        "kind": drive.kind,
        "summary": drive.summary(),
    }
    out.update(drive.described(lower_rad, upper_rad))
    return out


def model_summary(
    robot: Robot, leg_name: str, drives: tuple[Drive, Drive], stance_height_m: float
) -> dict[str, Any]:
    """Plain data of ``scalf-opt model``.

    Args:
        robot: The robot.
        leg_name: The leg to describe.
        drives: Its (hip pitch, knee) drives.
        stance_height_m: Hip height of the standing posture shown [m].
    """
    leg = robot.leg(leg_name)
    lo, hi = leg.lower_limits_rad, leg.upper_limits_rad
    q = LegKinematics(leg).inverse(np.array([0.0, -stance_height_m]))
    gravity = pin.computeGeneralizedGravity(leg.model, leg.model.createData(), q)
    joints = []
    for i, role in enumerate(JOINT_ROLES):
        joints.append(
            {
                "role": role,
                "name": leg.joint_names[i],
                "axis": "+y" if leg.axis_signs[i] > 0 else "-y",
                "lower_rad": float(lo[i]),
                "upper_rad": float(hi[i]),
                "effort_limit_nm": float(leg.effort_limits_nm[i]),
                "velocity_limit_rad_s": float(leg.velocity_limits_rad_s[i]),
                "drive": drive_summary(drives[i], lo[i], hi[i]),
            }
        )
    return {
        "robot": robot.name,
        "urdf": str(robot.urdf_path),
        "total_mass_kg": robot.total_mass_kg,
        "trunk_mass_kg": robot.trunk_mass_kg,
        "trunk_com_m": robot.trunk_com_m.tolist(),
        "leg": leg.name,
        "hind": leg.is_hind,
        "hip_origin_m": leg.hip_origin_m.tolist(),
        "foot_lateral_m": leg.foot_lateral_m,
        "links": dict(zip(("thigh", "shank"), leg_link_table(leg), strict=True)),
        "joints": joints,
        "standing_posture": {
            "stance_height_m": stance_height_m,
            "q_rad": q.tolist(),
            "gravity_torques_nm": np.asarray(gravity).tolist(),
        },
    }
