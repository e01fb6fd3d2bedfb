"""Plain-text reports: the leg model as Pinocchio sees it and paper-style energy tables."""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from scalf_opt import paper_data
from scalf_opt.cycle import RobotCycle
from scalf_opt.gait import GaitSpec
from scalf_opt.kinematics import LegKinematics
from scalf_opt.reproduction import change_percent
from scalf_opt.robot import Leg, Robot

if TYPE_CHECKING:
    from scalf_opt.optimize.solve import SwingOptimum
    from scalf_opt.reproduction import Reproduction


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
    is_paper_setup = robot.preset.name == "scalf" and cycle.gait == GaitSpec()
    if title == "reference" and cycle.accounting == "paper" and is_paper_setup:
        ref = paper_data.REFERENCE_AVERAGE_POWER_W
        diff = cycle.average_power_w - ref
        change = change_percent(cycle.average_power_w, ref)
        lines.append(
            f"average total power          {cycle.average_power_w:10.2f} W   paper (Table 6): "
            f"{ref:.2f} W   difference {diff:+.2f} W ({change:+.1f} %)"
        )
    else:
        lines.append(f"average total power          {cycle.average_power_w:10.2f} W")
    lines += [
        f"cost of transport            {cycle.cost_of_transport:10.4f}     "
        f"(m = {cycle.total_mass_kg:.2f} kg; MIT Cheetah: {paper_data.MIT_CHEETAH_COT})",
        f"symmetry check |E_LF - E_RF|, |E_RH - E_LH| relative: {cycle.symmetry_error:.1e}",
    ]
    return "\n".join(lines)


def _signed(x: float) -> str:
    return f"{x:+.2f} %"


def paper_markdown(rep: Reproduction, robot: Robot) -> str:
    """The paper-reproduction report (Markdown): Tables 5 and 6 beside the paper's numbers."""
    from scalf_opt.reproduction import PAIR, RUNS, gap_percent, table6_rows

    g = rep.gait
    paper6 = paper_data.TABLE6_CHANGE_PERCENT
    lines = [
        "# SCalf paper reproduction: Tables 5 and 6",
        "",
        f"Robot `{robot.urdf_path.name}` ({robot.total_mass_kg:.2f} kg); "
        f"trot T = {g.period_s:g} s, duty {g.duty_cycle:g}, S = {g.step_length_m:g} m, "
        f"H = {g.clearance_m:g} m, "
        f"z0 = {g.stance_height_m:g} m, {g.sample_rate_hz:g} Hz; power `|tau qd| + |F_f v|`. "
        "LF and RH repeat RF and LH half a cycle later (the paper's symmetry; checked: "
        f"{rep.reference.symmetry_error:.1e}).",
        "",
        "## Table 5: trajectory parameters",
        "",
        "C1 is the hip angle's `cos(3 pi s)` amplitude, C2 the knee angle's `cos(2 pi s)` "
        "amplitude [deg] (see the README for the family); the paper's own basis was lost, so its "
        "values are not comparable number for number.",
        "",
        "| leg | run | C1 [deg] | C2 [deg] | iterations | evaluations | swing energy [J] "
        "| status |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for leg in PAIR:
        for key in ("pattern", "pattern_fine", "ipopt"):
            o = rep.optima[key][leg]
            lines.append(
                f"| {leg} | {RUNS[key][1]} | {o.theta[0]:.3f} | {o.theta[1]:.3f} | {o.iterations} |"
                f" {o.evaluations or '-'} | {o.swing_energy_j:.3f} | {o.status} |"
            )
        if leg == "RF":
            t5 = paper_data.TABLE5_RF
            lines.append(
                f"| RF | paper, pattern search | {t5['C1']} | {t5['C2']} | {t5['iterations']} | "
                "- | - | (Table 5) |"
            )
    rows = table6_rows(rep)
    lines += [
        "",
        "## Table 6: energy per cycle (simulation)",
        "",
        "| trajectory | RF swing [J] | RF cycle [J] | LH swing [J] | LH cycle [J] | total [J] | "
        "avg power [W] | RF swing | RF cycle | LH swing | LH cycle | total |",
        "|---|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['trajectory']} | {r['RF_swing_j']:.3f} | {r['RF_cycle_j']:.3f} | "
            f"{r['LH_swing_j']:.3f} | {r['LH_cycle_j']:.3f} | {r['total_energy_j']:.3f} | "
            f"{r['average_power_w']:.2f} | {_signed(float(r['RF_swing_change_pct']))} | "
            f"{_signed(float(r['RF_cycle_change_pct']))} | "
            f"{_signed(float(r['LH_swing_change_pct']))} | "
            f"{_signed(float(r['LH_cycle_change_pct']))} | "
            f"{_signed(float(r['total_change_pct']))} |"
        )
    lines.append(
        f"| paper: reference -> Fourier (Table 6) | | | | | | "
        f"{paper_data.REFERENCE_AVERAGE_POWER_W} -> {paper_data.OPTIMIZED_AVERAGE_POWER_W} | "
        f"{_signed(paper6['RF']['swing'])} | {_signed(paper6['RF']['cycle'])} | "
        f"{_signed(paper6['LH']['swing'])} | {_signed(paper6['LH']['cycle'])} | "
        f"{_signed(paper6['total']['total'])} |"
    )
    lines += [
        "",
        "## Validation: pattern search against the NLP optimum",
        "",
        "Both answers are evaluated with the exact, non-smooth energy.",
        "",
        "| leg | gap at precision 0.1 | gap at precision 1e-4 | Ipopt iterations | Ipopt status |",
        "|---|---|---|---|---|",
    ]
    for leg in PAIR:
        nlp = rep.optima["ipopt"][leg]
        lines.append(
            f"| {leg} | {gap_percent(rep.optima['pattern'][leg], nlp):+.4f} % | "
            f"{gap_percent(rep.optima['pattern_fine'][leg], nlp):+.5f} % | {nlp.iterations} | "
            f"{nlp.status} |"
        )
    if not rep.all_solved:
        lines += [
            "",
            "**Not every optimizer converged: see the status columns. Rows of a run "
            "that did not converge are left out of Table 6.**",
        ]
    ref_power = rep.reference.average_power_w
    lines += [
        "",
        "## Why the numbers differ from the paper",
        "",
        f"- The reference draws {ref_power:.1f} W against the paper's 671.52 W: the paper gives "
        "neither the stance height z0 (0.75 m here), nor the trunk's inertia, nor its exact "
        "stance trajectory and force treatment; the stance phase dominates the total.",
        "- The paper's Fourier basis and its Appendix A were lost. The paper family here has the "
        "same size (two coefficients per leg) but is our own design; the best of the 50 "
        "single-term pairs we scanned (`studies/paper_family_scan.py`). With two coefficients "
        "it cuts the swing energy by less than the paper's 26 %; the richer nested family shows "
        "how much a swing can save under the same constraints.",
        "- Constraints are the paper's implicit ones made explicit (joint limits, ground, "
        "cylinder stroke, at least H of clearance at mid-swing); the foot's mid-swing x is free.",
        "",
        "## Figures",
        "",
        "![Pattern search (the paper's Figure 8)](pattern_search.png)",
        "",
        "![RF swing foot paths and power](swing_paths.png)",
        "",
        f"Run time of the whole reproduction: {rep.wall_time_s:.1f} s.",
    ]
    return "\n".join(lines) + "\n"


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
