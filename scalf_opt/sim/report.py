"""The text table ``scalf-opt simulate`` prints: the same numbers as ``simulation.json``."""

from __future__ import annotations

from typing import Any

from scalf_opt.energy.cycle import energy_basis
from scalf_opt.types import LEG_NAMES


def _met(flag: bool) -> str:
    return "met" if flag else "NOT met"


def _change(value: float, base: float) -> str:
    return f"{100 * (value / base - 1):+7.2f} %" if base else "    n/a"


def _inverse_dynamics_rows(result: dict[str, Any]) -> list[str]:
    """Per leg: the plan's own energy and force, and the model's and the simulation's gaps."""
    plan = result["plan_inverse_dynamics"]
    rows = []
    for leg in LEG_NAMES:
        e, p = plan["joint_energy_per_phase_j"][leg], result["joint_energy_per_phase_j"][leg]
        rows.append(
            f"{leg:4s}  {e['stance']:10.3f}  {e['swing']:9.3f}  "
            f"{plan['stance_force_mean_n'][leg]:14.1f}   "
            f"{_change(p['stance']['model'], e['stance'])} / "
            f"{_change(p['swing']['model'], e['swing'])}        "
            f"{_change(p['stance']['simulated'], e['stance'])} / "
            f"{_change(p['swing']['simulated'], e['swing'])}"
        )
    return rows


DETAILS = "the plan followed exactly, the servo's work, contacts and joint stops"
"""What the whole report adds to the summary (:func:`simulation_report`)."""


def simulation_report(result: dict[str, Any], title: str, details: bool = True) -> str:
    """Trunk motion, foot forces and slip, joint energy against the model, checks and goals.

    ``details``: also :data:`DETAILS` (the summary leaves them out).
    """
    goals = result["goals"]
    ensemble = "ensemble" in result
    basis = energy_basis(result["loads"], result["accounting"], result["gait"]["sample_rate_hz"])
    lines = [
        title,
        f"the model it is compared with: {basis}",
        "",
        f"trunk height fluctuation  {1e3 * result['trunk_height_fluctuation_m']:8.3f} mm   "
        f"goal <= {1e3 * goals['trunk_height_fluctuation_at_most_m']:.2g} mm: "
        f"{_met(goals['trunk_height_met'])}   (mean {1e3 * result['trunk_height_mean_m']:.2f} "
        f"mm, planned {1e3 * result['trunk_height_planned_m']:.2f} mm)",
        f"trunk pitch peak          {1e3 * result['trunk_pitch_peak_rad']:8.3f} mrad",
        f"forward speed             {result['forward_speed_m_s']:8.4f} m/s  "
        f"(planned {result['planned_speed_m_s']:.4f} m/s)",
        "",
        "leg   force peak [N]  mean [N]  model mean [N]  slip [mm]  "
        "energy sim [J]  model [J]  difference"
        + (
            " spread [pts]   nominal: stance / swing"
            if ensemble
            else "   stance / swing difference"
        ),
    ]
    energy = result["joint_energy_per_cycle_j"]
    phases = result["joint_energy_per_phase_j"]
    for leg in LEG_NAMES:
        e, p = energy[leg], phases[leg]
        spread = f"{100 * e['relative_difference_spread']:11.2f}  " if ensemble else ""
        lines.append(
            f"{leg:4s}  {result['stance_force_peak_n'][leg]:14.1f}  "
            f"{result['stance_force_mean_n'][leg]:8.1f}  "
            f"{result['model_stance_force_mean_n'][leg]:14.1f}  "
            f"{1e3 * result['foot_slip_m'][leg]:9.3f}  {e['simulated']:14.3f}  "
            f"{e['model']:9.3f}  {100 * e['relative_difference']:+9.2f} %   {spread}"
            f"{100 * p['stance']['relative_difference']:+7.2f} % / "
            f"{100 * p['swing']['relative_difference']:+7.2f} %"
        )
    total, power = result["total_energy_per_cycle_j"], result["average_total_power_w"]
    lines += [
        f"total {'':62s}{total['simulated']:14.3f}  {total['model']:9.3f}  "
        f"{100 * total['relative_difference']:+9.2f} %"
        + (f"   {100 * total['relative_difference_spread']:11.2f}" if ensemble else ""),
        f"average total power       {power['simulated']:8.2f} W simulated, "
        f"{power['model']:.2f} W model (mean of {result['cycles_averaged']} cycles after the "
        "first" + ("; the nominal referee's)" if ensemble else ")"),
        "touch-down vs plan (negative: early) "
        + ", ".join(
            f"{leg} {1e3 * result['touchdown_timing_s'][leg]:+.1f} ms" for leg in LEG_NAMES
        ),
        energy_goal_line(result),
    ]
    if details:
        lines += _details(result)
        if ensemble:
            lines += ensemble_lines(result)
    return "\n".join(lines + _checks_and_saving(result))


def energy_goal_line(result: dict[str, Any]) -> str:
    """The joint-energy verdict: the nominal referee's, or the ensemble's median and spread."""
    goals = result["goals"]
    goal = goals["joint_energy_relative_difference_at_most"]
    line = f"goal: joint energy within {100 * goal:.0f} % of the model's on every leg"
    failure = run_failure(result)
    if "ensemble" not in result:
        if failure is not None:
            return f"{line}: NOT met ({failure})"
        return f"{line}: {_met(goals['joint_energy_met'])}"
    n = len(result["ensemble"]["members"])
    line += f" in the median of {n} referees, spread at most {100 * goal:.0f} points: "
    if failure is not None:
        return line + f"NOT refereeable ({failure})"
    if not goals["refereeable"]:
        spread = result["ensemble"]["largest_spread"]
        return line + f"NOT refereeable (the referees disagree by up to {100 * spread:.2f} points)"
    return line + _met(goals["joint_energy_met"])


def run_failure(result: dict[str, Any], robot: str = "the robot") -> str | None:
    """Why the run(s) of ``result`` measured no verdict, in words; ``None`` when they did.

    An ensemble's: ``MuJoCo's integration diverged under: <members>`` and ``<robot> fell
    under: <members>``; one run's: ``MuJoCo's integration diverged at t = ... s (<check>)``
    and ``<robot> fell at t = ... s``; joined by ``; `` when both.
    """
    ensemble = result.get("ensemble") or {}
    reasons = []
    if ensemble.get("diverged") or ensemble.get("fell"):
        if ensemble.get("diverged"):
            reasons.append(
                f"MuJoCo's integration diverged under: {', '.join(ensemble['diverged'])}"
            )
        if ensemble.get("fell"):
            reasons.append(f"{robot} fell under: {', '.join(ensemble['fell'])}")
    else:
        if result.get("diverged_at_s") is not None:
            reasons.append(
                f"MuJoCo's integration diverged at t = {result['diverged_at_s']:.3f} s "
                f"({result.get('divergence')})"
            )
        if result.get("fell_at_s") is not None:
            reasons.append(f"{robot} fell at t = {result['fell_at_s']:.3f} s")
    return "; ".join(reasons) or None


def ensemble_lines(result: dict[str, Any]) -> list[str]:
    """The ensemble's members: each one's differences and saving."""
    lines = [
        "",
        "referee ensemble (each member changes one setting of the nominal referee; the verdict "
        "is their median):",
        f"{'member':30s} {'RF':>8s} {'LH':>8s} {'LF':>8s} {'RH':>8s} {'total':>8s}  saving   "
        "saturated",
    ]
    for m in result["ensemble"]["members"]:
        saving = m["saving_simulated_percent"]
        lines.append(
            f"{m['name']:30s} "
            + " ".join(f"{100 * m['relative_difference'][leg]:+7.2f}%" for leg in LEG_NAMES)
            + f" {100 * m['total_relative_difference']:+7.2f}%  "
            + ("    n/a" if saving is None else f"{saving:+6.2f}%")
            + f"  {100 * m['torque_saturation_fraction']:6.2f} %"
            + ("" if m.get("fell_at_s") is None else f"  fell at {m['fell_at_s']:.3f} s")
            + (
                ""
                if m.get("diverged_at_s") is None
                else f"  diverged at {m['diverged_at_s']:.3f} s ({m.get('divergence')})"
            )
        )
    return lines


def _details(result: dict[str, Any]) -> list[str]:
    """The report's middle: the plan followed exactly, the servo, contacts and joint stops."""
    return [
        "",
        "the plan followed exactly (MuJoCo's inverse dynamics of the whole robot on the plan, "
        "foot forces by the sagittal minimum norm, as --loads whole-body-sagittal):",
        "leg   stance [J]  swing [J]  mean force [N]   model vs it: stance / swing   "
        "simulation vs it: stance / swing",
        *_inverse_dynamics_rows(result),
        "",
        "servo: leg   joints' work net / gross [J]   of it the PD feedback's net / gross [J]   "
        "feedback torque rms / torque rms",
        *(
            f"       {leg:4s}  {w['joints_net']:+10.3f} / {w['joints_gross']:9.3f}"
            f"   {w['feedback_net']:+23.3f} / {w['feedback_gross']:9.3f}"
            f"   {w['feedback_torque_rms_over_torque_rms']:10.3f}"
            for leg, w in result["servo_work_per_cycle_j"].items()
        ),
        f"contacts and joint limits: {result['constraint_work_per_cycle_j']:+.3f} J per cycle; "
        "stance feet pushing against each other along x: "
        + ", ".join(
            f"{pair} peak {f['peak']:.1f} N, mean {f['mean']:.1f} N"
            for pair, f in result["internal_horizontal_force_n"].items()
        ),
        "closest approach to a joint stop, planned / simulated [mrad] (negative: beyond): "
        + ", ".join(
            f"{leg} "
            + " ".join(
                f"{1e3 * p:.1f}/{1e3 * q:.1f}"
                for p, q in zip(c["planned"], c["simulated"], strict=True)
            )
            for leg, c in result["joint_stop_clearance_rad"].items()
        ),
    ]


def _checks_and_saving(result: dict[str, Any]) -> list[str]:
    """The report's end: the checks, the referee's settings, the saving over the reference."""
    lines = [
        "",
        "checks: mean vertical ground force / weight "
        f"{result['checks']['mean_vertical_ground_force_over_weight']:.5f}; "
        "energy balance error / gross joint work "
        f"{result['checks']['energy_balance_error_over_gross_work']:+.1e}; "
        "torque saturation "
        f"{100 * max(result['torque_saturation_fraction'].values()):.2f} % of steps",
    ]
    settings = result["settings"]
    lines += [
        f"referee: servo {settings['servo_bandwidth_hz']:.2f} Hz (damping ratio "
        f"{settings['servo_damping_ratio']:g}), contact time constant "
        f"{1e3 * settings['contact_time_constant_s']:.3f} ms, feet "
        f"{1e3 * settings['foot_radius_m']:.2f} mm, step {1e3 * settings['timestep_s']:g} ms"
        + (" (derived from the leg length L)" if result.get("settings_derivation") else ""),
        *(f"MuJoCo model repair: {repair}" for repair in result.get("model_repairs", [])),
    ]
    if "reference_skipped" in result:
        lines += ["", f"reference not simulated: {result['reference_skipped']}"]
    saving = result.get("saving_vs_reference")
    if saving is not None:
        reference = result["reference"]["total_energy_per_cycle_j"]
        legs = result["reference"]["joint_energy_per_cycle_j"].values()
        worst = max(legs, key=lambda e: abs(e["relative_difference"]))
        spread = (
            f", spread {100 * max(e['relative_difference_spread'] for e in legs):.2f} points"
            if "relative_difference_spread" in worst
            else ""
        )
        failure = run_failure(result["reference"], robot="it")
        if failure is not None:
            spread += f"; {failure}"
        lines += [
            "",
            f"reference swing, simulated the same way: {reference['simulated']:.3f} J per cycle "
            f"(model {reference['model']:.3f} J; its worst leg "
            f"{100 * worst['relative_difference']:+.2f} %{spread})",
            f"saving over the reference: model {saving['model_percent']:+.2f} %, simulated "
            f"{saving['simulated_percent']:+.2f} %"
            + (
                f" (the ensemble's median; spread {saving['simulated_percent_spread']:.2f} points)"
                if "simulated_percent_spread" in saving
                else ""
            )
            + f"; goal same sign, within a third: {_met(saving['same_sign_within_a_third_met'])}",
        ]
    return lines
