"""The text table of ``scalf-opt analyze-log`` (the paper's Table 7 layout, for one log)."""

from __future__ import annotations

from scalf_opt.logs.analysis import LogAnalysis

_PERIOD_SOURCES = {
    "--period": "given",
    "contact": "median time between touch-downs",
    "gait": "the gait's",
    "motion": "the motion's, from the {signals}' self-similarity",
}

# a bag's time origin is its first message (scalf_opt.logs.bag_log)


def _phases(analysis: LogAnalysis) -> str:
    """Where the stance and swing phases come from: the log's contact, or a trot schedule."""
    if analysis.duty_cycle is None:
        return "phases from the contact column"
    return (
        f"phases from a trot schedule at duty {analysis.duty_cycle:g}, t = 0 where RF and LH "
        "touch down (no contact column: the duty of --gait, of --plan, else of the robot's "
        "default trot)"
    )


_CYLINDER_WORDS = {
    "log": "cylinder log",
    "signals": "lengths",
    "robot": "the robot (4 legs)",
    "velocity": "cylinder velocity",
    "measured": "the log's own (measured speeds, no filter)",
    "power": "sum |F v|",
    "loss": "friction heat",
    "total": "with the cylinders' friction heat (the model's Stribeck law at the measured "
    "velocity)",
}

_WORDS = {
    "cylinder": _CYLINDER_WORDS,
    "metered cylinder": {
        **_CYLINDER_WORDS,
        "loss": "drive beyond",
        "total": "drawn by the drives (their model at the measured state: valve-controlled "
        "cylinders draw supply pressure x flow)",
    },
    "joint": {
        "log": "joint log",
        "signals": "joint angles",
        "robot": "the hip pitch and knee joints (4 legs; every joint with --mapping joint_state)",
        "velocity": "joint velocity",
        "measured": "the log's own (measured rates, no filter)",
        "power": "sum |tau qd|",
        "loss": "drive beyond",
        "total": "drawn by the drives (their model at the measured state)",
    },
}
"""The words of the kinds of log: a cylinder log (of cylinders whose friction heat the drives
add, SCalf's; or of cylinders that meter their own input power, valve-controlled ones) and a joint
log (a robot without cylinders, :mod:`scalf_opt.logs.joint_log`)."""


def log_report(
    analysis: LogAnalysis, velocity_source: str = "filter", kind: str = "cylinder"
) -> str:
    """Per leg and phase the mechanical energy per cycle; the robot's average power.

    ``velocity_source`` is ``measured`` when the log's own speeds were used; ``kind`` is
    ``cylinder``, ``metered cylinder`` or ``joint`` (:attr:`~scalf_opt.api.logs.LogResult
    .report_kind`).
    """
    words = _WORDS[kind]
    first = analysis.as_dict()
    filt = first["filter"]
    loss = words["loss"]
    lines = [
        f"{words['log']} {analysis.source}: legs {', '.join(analysis.legs)}, "
        f"{analysis.sample_rate_hz:.1f} Hz",
        f"gait period {analysis.period_s:.4g} s "
        f"({_PERIOD_SOURCES[analysis.period_source].format(signals=words['signals'])})",
        _phases(analysis),
        f"{words['velocity']}: degree-{filt['degree']} least-squares fit over "
        f"{1e3 * filt['window_s']:.0f} ms ({filt['samples']} samples)"
        if velocity_source == "filter"
        else f"{words['velocity']}: {words['measured']}",
        "",
        f"       mechanical energy {words['power']}, mean per complete cycle",
        f"leg   cycles   swing [J]   stance [J]   cycle [J]   {loss + ' [J]':>17s}",
    ]
    for leg, energy in analysis.legs.items():
        e = energy.mechanical_j
        lines.append(
            f"{leg:4s}  {len(energy.windows_s):6d}  {e['swing']:10.3f}  {e['stance']:11.3f}  "
            f"{e['cycle']:10.3f}  {energy.friction_heat_j:18.3f}"
        )
    total = {
        phase: sum(e.mechanical_j[phase] for e in analysis.legs.values())
        for phase in ("swing", "stance", "cycle")
    }
    heat = sum(e.friction_heat_j for e in analysis.legs.values())
    lines += [
        f"total {'':6s}  {total['swing']:10.3f}  {total['stance']:11.3f}  {total['cycle']:10.3f}  "
        f"{heat:18.3f}",
        "",
        f"average power of {words['robot'].replace('4 legs', f'{len(analysis.legs)} legs')}: "
        f"{analysis.average_power_w:.2f} W mechanical; {analysis.average_total_power_w:.2f} W "
        f"{words['total']}",
    ]
    return "\n".join(lines) + "\n"
