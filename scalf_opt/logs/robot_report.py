"""The text report of ``scalf-opt analyze-log`` for a robot's own log (every joint)."""

from __future__ import annotations

from typing import Any


def robot_log_report(data: dict[str, Any]) -> str:
    """The report of :meth:`scalf_opt.api.robot_logs.RobotLogResult.to_dict`'s data."""
    velocity = (
        "the log's own rates" if data["velocity_source"] == "measured" else "the angles filtered"
    )
    methods = sorted({leg["contact_method"] for leg in data["legs"].values()})
    lines = [
        f"robot log {data['source']} (mapping {data['mapping']}), "
        f"{data['provenance']['robot']}: {data['sample_rate_hz']:.5g} Hz, joint rates "
        f"from {velocity}, contacts from the {' and '.join(methods)}",
        "mechanical energy sum |tau qd| per cycle, each leg's cycles from its own touch-downs",
        "",
        "leg   period [s]   duty   cycles   stance [J]   swing [J]   cycle [J]   contacts",
    ]
    for name, leg in data["legs"].items():
        e = leg["mechanical_energy_per_cycle_j"]
        lines.append(
            f"{name:4s}  {leg['period_s']:10.4f}  {leg['duty_cycle']:5.3f}  {leg['cycles']:7d}  "
            f"{e['stance']:11.3f}  {e['swing']:10.3f}  {e['cycle']:10.3f}   {leg['contact_method']}"
        )
    lines += ["", "joint                       leg   model   stance [J]   swing [J]   power [W]"]
    for joint, j in data["joints"].items():
        lines.append(
            f"{joint[:26]:26s}  {j['leg']:4s}  {'yes' if j['in_sagittal_model'] else 'no':5s}  "
            f"{j['stance_j']:11.3f}  {j['swing_j']:10.3f}  {j['average_power_w']:10.3f}"
        )
    count = len(data["joints"])
    lines += [
        "",
        f"average power of the robot (every leg joint in the log: {count}): "
        f"{data['average_power_w']:.2f} W; "
        f"the joints the sagittal model leaves out do {100 * data['left_out_share']:.1f} % of it",
    ]
    if data["cost_of_transport"] is not None:
        lines.append(
            f"speed {data['speed_m_s']:.4g} m/s ({data['speed_source']}), mass "
            f"{data['mass_kg']:.4g} kg: cost of transport {data['cost_of_transport']:.4f} "
            "(mechanical)"
        )
    else:
        lines.append("no speed (give --speed or an odometry topic): no cost of transport")
    lines += [_note(note) for note in data["notes"]]
    if "model_comparison" in data:
        lines += ["", *comparison_lines(data["model_comparison"])]
    return "\n".join(lines)


def comparison_lines(c: dict[str, Any]) -> list[str]:
    """The log against the model at its gait, joint by joint."""
    g = c["gait"]
    lines = [
        f"against the {c['model']} model at the log's gait (T {g['period_s']:.4g} s, duty "
        f"{g['duty_cycle']:.3f}, step {g['step_length_m']:.4g} m, stance height "
        f"{g['stance_height_m']:.4g} m; {c['loads']} loads; the reference swing)",
        "joint                       leg   measured [J]   planned [J]   ratio",
    ]
    for joint, j in c["joints"].items():
        ratio = "not modelled" if j["ratio"] is None else f"{j['ratio']:.3f}"
        lines.append(
            f"{joint[:26]:26s}  {j['leg']:4s}  {j['measured_j']:12.3f}  {j['planned_j']:12.3f}"
            f"   {ratio}"
        )
    lines += [_note(note) for note in c["notes"]]
    return lines


def _note(text: str) -> str:
    """A note line: ``warning: ...`` as it is, anything else as ``note: ...``."""
    return text if text.startswith("warning:") else f"note: {text}"
