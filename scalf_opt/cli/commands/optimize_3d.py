"""``scalf-opt optimize --model 3d``: one periodic trot cycle of the whole robot in 3-D."""

from __future__ import annotations

import argparse
import math
from dataclasses import replace
from typing import TYPE_CHECKING, Any, Literal

from scalf_opt.cli.options import check_output_dir, friction_of, load_gait, load_robot
from scalf_opt.energy.loads import DEFAULT_LOADS
from scalf_opt.errors import ConfigError, GaitError
from scalf_opt.io.whole_body_summary import cycle_summary
from scalf_opt.locomotion.periodic_spline import READS_PER_INTERVAL
from scalf_opt.locomotion.swing.names import DEFAULT_FAMILY
from scalf_opt.types import LEG_NAMES

if TYPE_CHECKING:
    from scalf_opt.energy.margins import LimitMargins
    from scalf_opt.optimize.whole_body_nlp import CycleProblem

__all__ = ["cycle_report", "cycle_summary", "run_3d"]

DEFAULT_3D_RATE_HZ = 100.0
"""The 3-D cycle's node rate unless ``--rate`` says otherwise [Hz] (the ten-times rule refines
it where the energy needs more)."""

SAGITTAL_ONLY = {
    "family": DEFAULT_FAMILY,
    "leg": "PAIR",
    "bound": False,
    "free_stance": False,
    "starts": 1,
    "precision": None,
    "loads": DEFAULT_LOADS,
}
"""``optimize`` options of the sagittal swing problem and their defaults: the 3-D model has no
swing family, legs to choose or stance search of its own, and its loads are its own contact
forces, so another value is refused."""


def refuse_sagittal_options(args: argparse.Namespace) -> None:
    """Refuse a sagittal-only option given with ``--model 3d`` (one line naming it).

    Raises:
        ConfigError: Such an option has a value other than its default.
    """
    for field, default in SAGITTAL_ONLY.items():
        if getattr(args, field, default) != default:
            option = "--" + field.replace("_", "-")
            raise ConfigError(
                f"{option} is an option of the sagittal model; --model 3d optimizes every joint "
                "of the whole cycle (leave it out)",
                field=field,
            )
    from scalf_opt.optimize.solvers import DEFAULT_SOLVER

    if getattr(args, "method", DEFAULT_SOLVER) != DEFAULT_SOLVER:
        raise ConfigError("--method: --model 3d is solved by Ipopt only", field="method")


def build_problem(
    args: argparse.Namespace, margins: LimitMargins
) -> tuple[CycleProblem, float, str]:
    """The 3-D problem the options describe, its node rate [Hz] and a line saying so."""
    from scalf_opt.energy.whole_body import WholeBodyPhysics
    from scalf_opt.locomotion.contact_schedule import trot_schedule
    from scalf_opt.optimize.whole_body_nlp import CycleProblem

    robot = load_robot(args)
    duty, rate = args.duty_cycle, args.sample_rate_hz
    # the sagittal gait needs a duty factor of 0.5 or more and four samples per phase; the 3-D
    # schedule takes 0.2..0.8, and its driver starts on a grid of at least three nodes per phase
    args.duty_cycle = args.sample_rate_hz = None
    gait = load_gait(args, robot)
    args.duty_cycle, args.sample_rate_hz = duty, rate
    duty = gait.duty_cycle if duty is None else duty
    rate = DEFAULT_3D_RATE_HZ if rate is None else rate
    if not (math.isfinite(rate) and rate > 0):
        raise ConfigError(f"--rate {rate:g} must be > 0 [Hz]", field="sample_rate_hz")
    try:
        schedule = trot_schedule(gait.period_s, duty, rate)
    except GaitError as exc:
        raise GaitError(f"--duty {duty:g}: {exc}", field="duty_cycle") from exc
    physics = WholeBodyPhysics.of(robot)
    free = None
    if getattr(args, "period_range", None) is not None:
        from scalf_opt.cli.commands.gait_3d import period_range

        free = period_range(args.period_range, gait.period_s)
        if not free[0] <= gait.period_s <= free[1]:
            raise ConfigError(
                f"--period {gait.period_s:g}: outside --period-range {args.period_range} (the "
                "first period must lie in the range)",
                field="period_s",
            )
    # the step length S is the trunk's travel over a stance, S = v d T (the sagittal gait's)
    speed = args.speed if args.speed is not None else gait.step_length_m / (duty * gait.period_s)
    problem = CycleProblem(
        physics,
        schedule,
        speed,
        gait.stance_height_m,
        gait.clearance_m,
        args.friction,
        margins,
        args.accounting,
        free,
    )
    flight = gait.period_s * max(0.0, 0.5 - duty)
    line = (
        f"3-D whole-body trot on {robot.name}: T={gait.period_s:g} s, duty {duty:g}"
        + (f" (flight {1e3 * flight:.0f} ms twice per cycle)" if flight > 0 else "")
        + f", {speed:.3g} m/s (stride {speed * gait.period_s:.3g} m), H={gait.clearance_m:.3g} m, "
        f"start z0={gait.stance_height_m:.3g} m, friction {args.friction:g}, "
        f"accounting '{args.accounting}'"
        + (f"; the period free in {free[0]:g}..{free[1]:g} s" if free else "")
    )
    return problem, rate, line


REFERENCE_LINE = (
    "the reference trot balanced on the whole robot: the motion nearest the kinematic reference "
    "(trunk level at constant speed, feet on minimum-jerk paths) that contact forces in their "
    "cones can carry, within every limit; not optimized for energy"
)
"""What ``evaluate --model 3d`` reports, in words (its objective ``"reference"``)."""


def run_3d(
    args: argparse.Namespace,
    margins: LimitMargins,
    objective: Literal["energy", "reference"] = "energy",
) -> int:
    """Exit 0 when the cycle converged, 3 when it did not (unless accepted).

    ``margins``: the limit margins the options give (``optimize``'s). ``objective``: the NLP's
    (:class:`~scalf_opt.optimize.whole_body_nlp.CycleProblem`): ``"energy"`` for ``optimize``,
    ``"reference"`` for ``evaluate`` (the reference trot balanced).
    """
    from scalf_opt.cli.progress import ProgressBar
    from scalf_opt.io.whole_body_export import write_cycle
    from scalf_opt.optimize.whole_body_driver import optimize_cycle

    check_output_dir(args.out)
    refuse_sagittal_options(args)
    friction_of(args)
    problem, rate, line = build_problem(args, margins)
    problem = replace(problem, objective=objective)
    label = f"{args.command} --model 3d"
    with ProgressBar(None, label, enabled=not args.quiet) as bar:
        result = optimize_cycle(problem, rate, bar.step)
    console = args.console
    console.text(line)
    if objective == "reference":
        console.text(REFERENCE_LINE)
    summary = cycle_summary(problem, result)
    console.json(summary)
    console.text(cycle_report(problem, summary))
    written = []
    accept = getattr(args, "accept_unconverged", False)
    if args.out is not None and (result.converged or accept):
        written = write_cycle(args.out, summary, result.plan, problem.accounting)
        console.text("wrote " + " and ".join(str(p) for p in written))
    if not result.converged:
        console.error(f"not converged: {result.failure()}")
        return 0 if accept else 3
    return 0


def trunk_line(trunk: dict[str, list[float]]) -> str:
    """The trunk's height, roll and pitch ranges in words (degrees at the edge)."""
    roll = [math.degrees(v) for v in trunk["roll_rad"]]
    pitch = [math.degrees(v) for v in trunk["pitch_rad"]]
    return (
        f"trunk                    height {trunk['height_m'][0]:.3f}..{trunk['height_m'][1]:.3f}"
        f" m, roll {roll[0]:+.2f}..{roll[1]:+.2f} deg, pitch {pitch[0]:+.2f}..{pitch[1]:+.2f} deg"
    )


GRID_SETTLED = 0.01
"""A finer grid that moves the answer's energy by at most this share has settled it (the
report's "finer grid" line; a share, 1 %)."""


def grid_line(data: dict[str, Any]) -> str:
    """How much the last grid moved the answer (``grid_change`` of :func:`cycle_summary`)."""
    change, nodes = data.get("grid_change"), data.get("grid_change_from_nodes")
    label = "finer grid               "
    if change is None:
        return f"{label}not measured: every solve on {data['nodes']} nodes"
    verdict = (
        f"settled within {100 * GRID_SETTLED:g} %"
        if abs(change) <= GRID_SETTLED
        else "a finer grid may still find a cheaper plan"
        if change < 0
        else "the coarser grid's plan spends less: the finer grid ended on another local optimum"
    )
    return (
        f"{label}{100 * change:+.2f} % from the {nodes}-node optimum (both at 10x the rate): "
        f"{verdict}"
    )


def cycle_report(problem: CycleProblem, data: dict[str, Any]) -> str:
    """The run in words and a table, from its :func:`cycle_summary` ``data``."""
    lines = [""]
    for solve in data["solves"]:
        reads = solve.get("reads_per_interval", READS_PER_INTERVAL)
        denser = f" (read at {reads} points each)" if reads != READS_PER_INTERVAL else ""
        lines.append(
            f"Ipopt on {solve['nodes']:4d} nodes{denser}: {solve['status']} in "
            f"{solve['iterations']} "
            f"iterations ({solve['seconds']:.1f} s), {solve['energy_per_cycle_j']:.3f} J per "
            f"cycle, {100 * solve['rate_difference']:+.2f} % at 10x the rate"
        )
    lines += ["", "leg   cycle [J]   per joint [J]"]
    joints = data["joint_energy_per_cycle_j"]
    for i, leg in enumerate(LEG_NAMES):
        own = [
            f"{name} {joints[name]:.3f}"
            for name, owner in zip(
                problem.physics.joint_names, problem.physics.joint_legs, strict=True
            )
            if owner == i
        ]
        lines.append(f"{leg:4s} {data['leg_energy_per_cycle_j'][leg]:10.3f}   " + ", ".join(own))
    check, trunk = data["check_at_10x"], data["trunk"]
    lines += [
        "",
        f"total energy per cycle   {data['energy_per_cycle_j']:10.3f} J at the nodes, "
        f"{data['energy_at_10x_j']:.3f} J at 10x the rate "
        f"({100 * data['rate_difference']:+.2f} %)",
        grid_line(data),
        f"cost of transport        {data['cost_of_transport']:10.4f}",
        *(
            [
                f"period                   {data['period_s']:10.4f} s (free in "
                f"{data['period_range_s'][0]:g}..{data['period_range_s'][1]:g} s), stride "
                f"{data['stride_m']:.4f} m"
            ]
            if data.get("period_range_s")
            else []
        ),
        trunk_line(trunk),
        "between the nodes        trunk wrench left "
        f"{100 * check['trunk_wrench_share_of_weight']:.2f} % of the weight, stance slip "
        f"{1e3 * check['stance_slip_m']:.2f} mm, swing floor "
        f"{1e3 * check['swing_floor_m']:+.2f} mm",
    ]
    if data["pinned_by"]:
        from scalf_opt.cli.commands.gait_3d import pinned_words

        lines.append(f"pinned at                {pinned_words('; '.join(data['pinned_by']))}")
    else:
        period = " and the period's range" if data.get("period_range_s") else ""
        lines.append(
            "pinned at                no limit: every joint's range, rate, effort and drive "
            f"bound (less margins){period} keep room"
        )
    estimated = [j for j, o in data["drives"].items() if o != "actuator file"]
    if estimated:
        lines.append(
            f"drives not in the actuator file: {', '.join(estimated)} "
            f"({data['drives'][estimated[0]]})"
        )
    return "\n".join(lines)
