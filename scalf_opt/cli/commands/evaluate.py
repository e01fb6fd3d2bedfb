"""``scalf-opt evaluate``: the energy of the reference trajectory, or of a saved optimum."""

from __future__ import annotations

import argparse
from pathlib import Path

from scalf_opt.cli.options import (
    add_accept_unconverged,
    add_friction,
    add_gait,
    add_loads,
    add_robot,
    check_output_dir,
    friction_of,
    gait_origin,
    load_gait,
    load_robot,
    warn_without_effect,
)
from scalf_opt.errors import ConfigError

NAME = "evaluate"
HELP = "energy of the cubic-spline reference trajectory, or of a saved optimum (--swing)"
EXAMPLES = (
    ("scalf-opt evaluate", "the reference swing on SCalf's trot (the paper's Table 6)"),
    ("scalf-opt evaluate --robot go1 --period 0.4 --out results/go1", "another robot and period"),
    ("scalf-opt evaluate --swing results/optimum --rate 1000", "a saved optimum at 1 kHz"),
    (
        "scalf-opt evaluate --model 3d --robot go1 --rate 25",
        "the reference trot balanced on the whole robot in 3-D (a minute or two)",
    ),
)
JSON = True


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    add_robot(parser)
    parser.add_argument(
        "--model",
        choices=("sagittal", "3d"),
        default="sagittal",
        help="sagittal (default): the paper's model, two-joint legs under a trunk on a fixed "
        "line; 3d: the whole robot's trot cycle (free trunk, every joint, contact forces in "
        "friction cones): the balanced motion nearest the kinematic reference trot, solved by "
        "Ipopt (not optimized for energy; takes a minute or more)",
    )
    add_friction(parser)
    add_gait(parser, speed=True)
    add_loads(parser, saved=True)
    parser.add_argument(
        "--swing",
        type=Path,
        metavar="FILE",
        help="evaluate the optimum saved in FILE (the summary.json of optimize --out, or its "
        "folder) instead of the reference: at its gait and on its robot (a catalog robot's "
        "name) by default; any rate and accounting, the same timing and stance",
    )
    parser.add_argument(
        "--out", type=Path, metavar="DIR", help="write summary.json and samples.csv in DIR"
    )
    add_accept_unconverged(parser)


def run_reference_3d(args: argparse.Namespace) -> int:
    """``evaluate --model 3d``: the reference trot balanced on the whole robot.

    Exit 3 if a solve did not converge (nothing is written then), unless
    ``--accept-unconverged`` (written and marked so, exit 0).

    Raises:
        ConfigError: ``--swing`` or ``--loads`` given (options of the sagittal model).
    """
    from scalf_opt.cli.commands.optimize_3d import run_3d
    from scalf_opt.energy.loads import DEFAULT_LOADS
    from scalf_opt.energy.margins import DEFAULT_MARGINS

    if args.swing is not None:
        raise ConfigError(
            "--swing: --model 3d evaluates the reference trot; a saved 3-D cycle is read by "
            "simulate, view, figures and export --from",
            field="swing",
        )
    if args.loads is not None:
        raise ConfigError(
            "--loads is an option of the sagittal model; --model 3d carries the robot by its own "
            "contact forces (leave it out)",
            field="loads",
        )
    args.loads = DEFAULT_LOADS
    return run_3d(args, DEFAULT_MARGINS, objective="reference")


def run(args: argparse.Namespace) -> int:  # noqa: D103
    if args.model == "3d":
        return run_reference_3d(args)
    friction_of(args)  # refused here: an option of --model 3d
    if args.accept_unconverged:
        raise ConfigError(
            "--accept-unconverged is an option of --model 3d (the sagittal evaluate solves "
            "nothing)",
            field="accept_unconverged",
        )
    from scalf_opt.api import evaluate
    from scalf_opt.io.saved import read_saved_swings
    from scalf_opt.studies import paper_data
    from scalf_opt.viz.optimization_report import peaks_table, violation_lines
    from scalf_opt.viz.report import evaluate_report

    check_output_dir(args.out)
    saved_swings = read_saved_swings(args.swing) if args.swing is not None else None
    robot = load_robot(args, saved_swings)
    warn_without_effect(args, robot)
    base = saved_swings.gait if saved_swings is not None else None
    gait = load_gait(args, robot, base)
    result = evaluate(
        robot,
        gait,
        accounting=args.accounting,
        swing=args.swing,
        command=args.argv,
        loads=args.loads,
    )
    comparison, title = None, "reference"
    if result.swing is not None:
        families = sorted({f for f in result.swing.families.values() if f != "reference"})
        title = f"saved optimum ({', '.join(families)}, {result.swing.source})"
    elif paper_data.is_paper_setup(robot, gait, args.accounting, result.pipeline.loads):
        comparison = ("paper (Table 6)", paper_data.REFERENCE_AVERAGE_POWER_W)
    written = result.write(args.out) if args.out is not None else []
    console = args.console
    saved = f"the gait saved with the optimum {args.swing}" if args.swing is not None else None
    console.text(gait_origin(args, robot, saved))
    console.text(evaluate_report(result.cycle, robot.name, title=title, comparison=comparison))
    saved_rate = result.swing.rate_hz if result.swing is not None else None
    if saved_rate is not None and saved_rate > gait.sample_rate_hz:
        console.text(
            f"note: the optimum was found at {saved_rate:g} Hz; at {gait.sample_rate_hz:g} Hz its "
            "energy is resolved less finely"
        )
    console.text("\n" + peaks_table(result.peaks))
    for line in violation_lines(result.violations):
        console.text(line)
    console.json(result.to_dict())
    if written:
        console.text("wrote " + " and ".join(str(p) for p in written))
    return 0
