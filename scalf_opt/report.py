"""Plain-text reports: the leg model as Pinocchio sees it and paper-style energy tables."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from scalf_opt import paper_data
from scalf_opt.cycle import RobotCycle
from scalf_opt.kinematics import LegKinematics
from scalf_opt.robot import Leg, Robot


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


def model_report(robot: Robot, leg_name: str, stance_height_m: float | None = None) -> str:
    """Text of ``scalf-opt model``: a leg's parameters, actuators and nominal posture."""
    from scalf_opt.actuators import cylinder_length, load_actuators_for

    leg = robot.leg(leg_name, load_actuators_for(robot))
    lines = [
        f"robot {robot.preset.name}: {robot.urdf_path}",
        f"  total mass {robot.total_mass_kg:.3f} kg, trunk {robot.trunk_mass_kg:.3f} kg, "
        f"trunk COM {np.array2string(robot.trunk_com_m, precision=4)} m",
        f"leg {leg.name} ({'hind, mirror of a front leg' if leg.is_hind else 'front'}): "
        "Pinocchio reduced model, joints (hip pitch, knee)",
    ]
    for name, sign in zip(leg.joint_names, leg.axis_signs, strict=True):
        lines.append(f"  joint {name}: axis {'+' if sign > 0 else '-'}y")
    hip = leg.hip_origin_m
    lines.append(
        f"  hip-pitch origin (trunk frame): x={hip[0]:.4f} y={hip[1]:.4f} z={hip[2]:.4f} m; "
        f"foot lateral offset {leg.foot_lateral_m:.4f} m"
    )
    lines.append(
        "  link    mass [kg]  length [m]  COM dist [m]  COM angle [rad]  Iyy at COM [kg m^2]"
    )
    for label, row in zip(("thigh", "shank"), leg_link_table(leg), strict=True):
        lines.append(
            f"  {label:6s}  {row['mass_kg']:9.4f}  {row['length_m']:10.5f}  "
            f"{row['com_distance_m']:12.5f}  {row['com_angle_rad']:15.4f}  "
            f"{row['inertia_yy_kg_m2']:19.4f}"
        )
    lo, hi = leg.lower_limits_rad, leg.upper_limits_rad
    for i, name in enumerate(leg.joint_names):
        lines.append(
            f"  {name}: range [{lo[i]:.3f}, {hi[i]:.3f}] rad, effort {leg.effort_limits_nm[i]:.1f}"
            f" N m, velocity {leg.velocity_limits_rad_s[i]:.1f} rad/s"
        )
    for i, cyl in enumerate(leg.cylinders):
        if cyl is None:
            lines.append(f"  {leg.joint_names[i]}: ideal actuator (no cylinder data)")
            continue
        grid = np.linspace(lo[i], hi[i], 2001)
        lengths = np.array([float(cylinder_length(cyl, x)) for x in grid])
        lines.append(
            f"  cylinder {cyl.joint_name}: a={cyl.a_m * 1e3:.2f} mm b={cyl.b_m * 1e3:.2f} mm "
            f"phi = {math.degrees(cyl.phi_offset_rad):.2f} deg {'+' if cyl.angle_sign > 0 else '-'}"
            f" theta; length {lengths.min() * 1e3:.1f}..{lengths.max() * 1e3:.1f} mm over the "
            f"joint range (sweep {(lengths.max() - lengths.min()) * 1e3:.1f} mm, stroke "
            f"{cyl.stroke_m * 1e3:.1f} mm)"
        )
    height = stance_height_m if stance_height_m is not None else leg.default_stance_height_m
    q = LegKinematics(leg).inverse(np.array([0.0, -height]))
    grav = leg.gravity_torques(q)
    lines.append(
        f"nominal standing posture (foot {height:.3f} m straight below the hip): "
        f"q = ({q[0]:.4f}, {q[1]:.4f}) rad = ({math.degrees(q[0]):.2f}, "
        f"{math.degrees(q[1]):.2f}) deg; gravity torques ({grav[0]:.2f}, {grav[1]:.2f}) N m"
    )
    return "\n".join(lines)


def _pct(new: float, ref: float) -> float:
    return 100.0 * (new - ref) / ref


def evaluate_report(cycle: RobotCycle, robot: Robot, title: str = "reference") -> str:
    """Text of ``scalf-opt evaluate``: the paper's Table 6 layout for one trajectory."""
    g = cycle.gait
    lines = [
        f"{title} swing trajectory on {robot.preset.name}: trot T={g.period_s:g} s, "
        f"duty {g.duty_cycle:g}, S={g.step_length_m:g} m, H={g.clearance_m:g} m, "
        f"z0={g.stance_height_m:g} m, {g.sample_rate_hz:g} Hz, accounting '{cycle.accounting}'",
        "",
        "leg   swing [J]   stance [J]   cycle [J]   swing hip/knee [J]   stance hip/knee [J]",
    ]
    for name in ("RF", "LH", "LF", "RH"):
        if name not in cycle.legs:
            continue
        leg = cycle.legs[name]
        lines.append(
            f"{name:4s} {leg.swing_energy_j:10.3f} {leg.stance_energy_j:12.3f} "
            f"{leg.energy_j:11.3f}   {leg.swing.energy_j[0]:8.3f} / {leg.swing.energy_j[1]:7.3f}"
            f"   {leg.stance.energy_j[0]:8.3f} / {leg.stance.energy_j[1]:7.3f}"
        )
    lines += [
        "",
        f"total energy per cycle       {cycle.energy_j:10.3f} J "
        f"(mean of {g.cycles} identical periodic cycles)",
    ]
    if title == "reference" and cycle.accounting == "paper" and len(cycle.legs) == 4:
        ref = paper_data.REFERENCE_AVERAGE_POWER_W
        diff = cycle.average_power_w - ref
        lines.append(
            f"average total power          {cycle.average_power_w:10.2f} W   paper (Table 6): "
            f"{ref:.2f} W   difference {diff:+.2f} W ({_pct(cycle.average_power_w, ref):+.1f} %)"
        )
    else:
        lines.append(f"average total power          {cycle.average_power_w:10.2f} W")
    lines += [
        f"cost of transport            {cycle.cost_of_transport:10.4f}     "
        f"(m = {cycle.total_mass_kg:.2f} kg; MIT Cheetah: {paper_data.MIT_CHEETAH_COT})",
        f"symmetry check |E_LF - E_RF|, |E_RH - E_LH| relative: {cycle.symmetry_error:.1e}",
    ]
    return "\n".join(lines)
