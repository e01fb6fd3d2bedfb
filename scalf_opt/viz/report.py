"""Plain-text reports: the leg model as Pinocchio sees it and paper-style energy tables."""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from scalf_opt.energy.cycle import RobotCycle, change_percent
from scalf_opt.energy.loads import stance_loads


def model_report(data: dict[str, Any]) -> str:
    """Text of ``scalf-opt model`` from :func:`scalf_opt.io.model_summary.model_summary`."""
    hip = data["hip_origin_m"]
    lines = [
        f"robot {data['robot']}: {data['urdf']}",
        f"  total mass {data['total_mass_kg']:.3f} kg, trunk {data['trunk_mass_kg']:.3f} kg, "
        f"trunk COM {np.array2string(np.array(data['trunk_com_m']), precision=4)} m",
        f"leg {data['leg']} ({'hind, mirror of a front leg' if data['hind'] else 'front'}): "
        "Pinocchio reduced model, joints (hip pitch, knee)",
    ]
    lines += [f"  joint {j['name']}: axis {j['axis']}" for j in data["joints"]]
    lines += [
        f"  hip-pitch origin (trunk frame): x={hip[0]:.4f} y={hip[1]:.4f} z={hip[2]:.4f} m; "
        f"foot lateral offset {data['foot_lateral_m']:.4f} m",
        "  link    mass [kg]  length [m]  COM dist [m]  COM angle [rad]  Iyy at COM [kg m^2]",
    ]
    for label, row in data["links"].items():
        lines.append(
            f"  {label:6s}  {row['mass_kg']:9.4f}  {row['length_m']:10.5f}  "
            f"{row['com_distance_m']:12.5f}  {row['com_angle_rad']:15.4f}  "
            f"{row['inertia_yy_kg_m2']:19.4f}"
        )
    for j in data["joints"]:
        lines.append(
            f"  {j['name']}: range [{j['lower_rad']:.3f}, {j['upper_rad']:.3f}] rad, effort "
            f"{j['effort_limit_nm']:.1f} N m, velocity {j['velocity_limit_rad_s']:.1f} rad/s"
        )
    for j in data["joints"]:
        d = j["drive"]
        if "a_m" not in d:  # not a cylinder
            lines.append(f"  {j['name']}: {d['summary']}")
            continue
        lo, hi = d["length_range_m"]
        lines.append(
            f"  cylinder {d['joint']}: a={d['a_m'] * 1e3:.2f} mm b={d['b_m'] * 1e3:.2f} mm "
            f"phi = {math.degrees(d['phi_offset_rad']):.2f} deg "
            f"{'+' if d['angle_sign'] > 0 else '-'} theta; length {lo * 1e3:.1f}..{hi * 1e3:.1f} "
            f"mm over the joint range (sweep {(hi - lo) * 1e3:.1f} mm, stroke "
            f"{d['stroke_m'] * 1e3:.1f} mm)"
        )
        if d["kind"] != "cylinder":  # a cylinder with another power model
            lines.append(f"    {d['summary']}")
    posture = data["standing_posture"]
    q, grav = posture["q_rad"], posture["gravity_torques_nm"]
    lines.append(
        f"standing posture (foot {posture['stance_height_m']:.3f} m straight below the hip): "
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
        f"{title} swing trajectory on {robot_name}: {g.trot_text}, {g.sample_rate_hz:.4g} Hz, "
        f"accounting '{cycle.accounting}', loads '{cycle.loads}'",
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
        f"(loads '{cycle.loads}', {g.sample_rate_hz:.4g} Hz; mean of {g.cycles} periodic "
        "cycles)",
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
        f"stance feet: mean force {cycle.mean_stance_force_n:.1f} N; {cycle.loads} loads: "
        f"{stance_loads(cycle.loads).description}",
    ]
    model = stance_loads(cycle.loads)
    if model.unbalanced:
        lines.append(
            f"unbalanced moment ({model.unbalanced}): "
            f"peak {cycle.peak_unbalanced_moment_nm:.1f} N m"
        )
    return "\n".join(lines)
