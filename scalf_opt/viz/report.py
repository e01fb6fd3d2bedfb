"""Plain-text reports: the leg model as Pinocchio sees it and paper-style energy tables."""

from __future__ import annotations

import math

import numpy as np
import pinocchio as pin

from scalf_opt.actuators.cylinder import HydraulicCylinder
from scalf_opt.actuators.drive import Drive
from scalf_opt.actuators.valve_cylinder import ValveControlledCylinder
from scalf_opt.energy.cycle import RobotCycle, change_percent
from scalf_opt.model.kinematics import LegKinematics
from scalf_opt.model.leg import Leg
from scalf_opt.model.robot import Robot
from scalf_opt.optimize.solve import SwingOptimum


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


def model_report(
    robot: Robot, leg_name: str, drives: tuple[Drive, Drive], stance_height_m: float
) -> str:
    """Text of ``scalf-opt model``: a leg's parameters, drives and a standing posture.

    Args:
        robot: The robot.
        leg_name: The leg to describe.
        drives: Its (hip pitch, knee) drives.
        stance_height_m: Hip height of the standing posture shown [m].
    """
    leg = robot.leg(leg_name)
    lines = [
        f"robot {robot.name}: {robot.urdf_path}",
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
    for i, cyl in enumerate(drives):
        if not isinstance(cyl, HydraulicCylinder):
            lines.append(f"  {leg.joint_names[i]}: {cyl.summary()}")
            continue
        grid = np.linspace(lo[i], hi[i], 2001)
        lengths = np.array([float(cyl.length_m(x)) for x in grid])
        lines.append(
            f"  cylinder {cyl.joint_name}: a={cyl.a_m * 1e3:.2f} mm b={cyl.b_m * 1e3:.2f} mm "
            f"phi = {math.degrees(cyl.phi_offset_rad):.2f} deg {'+' if cyl.angle_sign > 0 else '-'}"
            f" theta; length {lengths.min() * 1e3:.1f}..{lengths.max() * 1e3:.1f} mm over the "
            f"joint range (sweep {(lengths.max() - lengths.min()) * 1e3:.1f} mm, stroke "
            f"{cyl.stroke_m * 1e3:.1f} mm)"
        )
        if isinstance(cyl, ValveControlledCylinder):
            lines.append(f"    {cyl.summary()}")
    q = LegKinematics(leg).inverse(np.array([0.0, -stance_height_m]))
    grav = pin.computeGeneralizedGravity(leg.model, leg.model.createData(), q)
    lines.append(
        f"standing posture (foot {stance_height_m:.3f} m straight below the hip): "
        f"q = ({q[0]:.4f}, {q[1]:.4f}) rad = ({math.degrees(q[0]):.2f}, "
        f"{math.degrees(q[1]):.2f}) deg; gravity torques ({grav[0]:.2f}, {grav[1]:.2f}) N m"
    )
    return "\n".join(lines)


def evaluate_report(
    cycle: RobotCycle,
    robot_name: str,
    title: str = "reference",
    comparison: tuple[str, float] | None = None,
) -> str:
    """Text of ``scalf-opt evaluate``: the paper's Table 6 layout for one trajectory.

    Args:
        cycle: The evaluated cycle.
        robot_name: Robot name for the title line.
        title: What the swing is (``reference``, ``optimized (joint-6, ipopt)``).
        comparison: ``(label, average power [W])`` to print beside ours, e.g. the paper's.
    """
    g = cycle.gait
    lines = [
        f"{title} swing trajectory on {robot_name}: trot T={g.period_s:g} s, "
        f"duty {g.duty_cycle:g}, S={g.step_length_m:g} m, H={g.clearance_m:g} m, "
        f"z0={g.stance_height_m:g} m, {g.sample_rate_hz:g} Hz, accounting '{cycle.accounting}'",
        "",
        "leg   swing [J]   stance [J]   cycle [J]   swing hip/knee [J]   stance hip/knee [J]",
    ]
    for name, leg in cycle.legs.items():
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
    power = f"average total power          {cycle.average_power_w:10.2f} W"
    if comparison is not None:
        label, ref = comparison
        diff = cycle.average_power_w - ref
        power += (
            f"   {label}: {ref:.2f} W   difference {diff:+.2f} W "
            f"({change_percent(cycle.average_power_w, ref):+.1f} %)"
        )
    lines += [
        power,
        f"cost of transport            {cycle.cost_of_transport:10.4f}     "
        f"(m = {cycle.total_mass_kg:.2f} kg)",
        f"symmetry check |E_LF - E_RF|, |E_RH - E_LH| relative: {cycle.symmetry_error:.1e}",
    ]
    return "\n".join(lines)


def optimum_report(optima: dict[str, SwingOptimum], reference: RobotCycle) -> str:
    """Text of ``scalf-opt optimize``: each leg's optimum against the reference swing."""
    lines = []
    for leg, o in optima.items():
        ref = reference.legs[leg].swing_energy_j
        params = ", ".join(f"{n}={v:.4f}" for n, v in zip(o.parameter_names, o.theta, strict=True))
        verdict = "solved" if o.success else "NOT SOLVED"
        lines.append(
            f"{leg}: {o.family} by {o.method}: {verdict} ({o.status}), {o.iterations} iterations"
            + (f", {o.evaluations} evaluations" if o.evaluations else "")
            + f", {o.wall_time_s:.2f} s"
        )
        if o.success:
            lines.append(
                f"  swing energy {o.swing_energy_j:.4f} J vs reference {ref:.4f} J "
                f"({change_percent(o.swing_energy_j, ref):+.2f} %)"
            )
            lines.append(f"  parameters [{o.unit}]: {params}")
        else:
            stats = ", ".join(f"{k}={v}" for k, v in sorted(o.stats.items()))
            lines.append(f"  solver statistics: {stats}")
    return "\n".join(lines)
