"""The text ``scalf-opt simulate`` prints for a 3-D cycle: the same numbers as its file."""

from __future__ import annotations

import math
from typing import Any

from scalf_opt.sim.report import energy_goal_line, ensemble_lines
from scalf_opt.types import LEG_NAMES


def _range(values: list[float] | None, scale: float, unit: str, digits: int) -> str:
    if values is None:
        return "n/a"
    return f"{scale * values[0]:.{digits}f}..{scale * values[1]:.{digits}f} {unit}"


def cycle_simulation_report(result: dict[str, Any], title: str, details: bool = True) -> str:
    """Trunk, feet and joint energy against the plan, the controller's share, the verdict.

    ``details``: also the referee ensemble's members and the settings.
    """
    ensemble = "ensemble" in result
    trunk = result["trunk"]
    deg = math.degrees(1.0)
    sagittal = result.get("sagittal_model_energy_per_cycle_j")
    compared = (
        "the 3-D model's energy of the sagittal plan (trunk level, abduction at zero, "
        f"minimum-norm forces) at 10x its node rate, accounting '{result['accounting']}'"
        if sagittal
        else f"the 3-D plan's energy at 10x its node rate, accounting '{result['accounting']}'"
    )
    lines = [
        title,
        f"the model it is compared with: {compared}",
        "",
        f"trunk height   {_range(trunk['height_m'], 1.0, 'm', 4)} "
        f"(plan {_range(trunk['plan_height_m'], 1.0, 'm', 4)})",
        f"trunk roll     {_range(trunk['roll_rad'], deg, 'deg', 2)} "
        f"(plan {_range(trunk['plan_roll_rad'], deg, 'deg', 2)}), "
        f"pitch {_range(trunk['pitch_rad'], deg, 'deg', 2)} "
        f"(plan {_range(trunk['plan_pitch_rad'], deg, 'deg', 2)})",
        "trunk off its plan: "
        + (
            "n/a"
            if trunk["position_error_max_m"] is None
            else f"at most {1e3 * trunk['position_error_max_m']:.1f} mm and "
            f"{deg * trunk['orientation_error_max_rad']:.2f} deg"
        )
        + f"; forward speed {trunk['forward_speed_m_s']:.4f} m/s "
        f"(plan {trunk['plan_forward_speed_m_s']:.4f} m/s)",
        "",
        "leg   force peak [N]  plan [N]  slip [mm]  touches in swing  feedback work  "
        "energy sim [J]  plan [J]  difference" + (" spread [pts]" if ensemble else ""),
    ]
    energy = result["joint_energy_per_cycle_j"]
    for leg in LEG_NAMES:
        e, peak = energy[leg], result["stance_force_peak_n"][leg]
        simulated_peak = "n/a" if peak["simulated"] is None else f"{peak['simulated']:.1f}"
        spread = f"{100 * e['relative_difference_spread']:12.2f}" if ensemble else ""
        lines.append(
            f"{leg:4s}  {simulated_peak:>14s}  {peak['model']:8.1f}  "
            f"{1e3 * result['foot_slip_m'][leg]:9.2f}  "
            f"{100 * result['unplanned_contact_fraction'][leg]:14.1f} %  "
            f"{100 * result['feedback_work_share'][leg]:11.1f} %  {e['simulated']:14.3f}  "
            f"{e['model']:8.3f}  {100 * e['relative_difference']:+8.2f} %{spread}"
        )
    total = result["total_energy_per_cycle_j"]
    saturated = max(result["torque_saturation_fraction"].values(), default=0.0)
    lines += [
        f"total {'':86s}{total['simulated']:14.3f}  {total['model']:8.3f}  "
        f"{100 * total['relative_difference']:+8.2f} %"
        + (f"{100 * total['relative_difference_spread']:12.2f}" if ensemble else ""),
        f"(each cycle after the first, {result['cycles_measured']} measured"
        + ("; the columns but energy are the nominal referee's)" if ensemble else ")")
        + f"; torque beyond an effort limit {100 * saturated:.2f} % of steps (worst joint)",
        energy_goal_line(result),
    ]
    if sagittal:
        lines.append(
            "the sagittal model's own energy per cycle (its loads, no abduction joints): "
            + ", ".join(f"{leg} {sagittal[leg]:.3f} J" for leg in LEG_NAMES)
        )
    if details:
        controller = result["controller"]
        lines += [
            "",
            f"controller: servo {result['settings']['servo_bandwidth_hz']:.3g} Hz on each swing "
            f"joint, trunk loop {controller['trunk_bandwidth_hz']:.3g} Hz through the stance "
            f"feet (friction pyramid {controller['friction_pyramid']:g}), foot placement "
            f"{1e3 * controller['foot_placement_s']:.0f} ms of the velocity error; time step "
            f"{1e3 * result['settings']['timestep_s']:.3g} ms, contact time constant "
            f"{1e3 * result['settings']['contact_time_constant_s']:.3g} ms, foot radius "
            f"{1e3 * result['settings']['foot_radius_m']:.3g} mm, friction "
            f"{result['settings']['foot_friction']:g}",
        ]
        if ensemble:
            lines += ensemble_lines(result)
    return "\n".join(lines)
