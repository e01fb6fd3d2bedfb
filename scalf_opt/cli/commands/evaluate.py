"""``scalf-opt evaluate``: the energy of the cubic-spline reference trajectory."""

from __future__ import annotations

import argparse
from pathlib import Path

from scalf_opt.cli.options import add_gait, add_robot, check_output_dir, load_gait, load_robot

NAME = "evaluate"
HELP = "energy of the cubic-spline reference trajectory"
JSON = True


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    add_robot(parser)
    add_gait(parser)
    parser.add_argument("--out", type=Path, help="write summary.json and samples.csv here")


def run(args: argparse.Namespace) -> int:  # noqa: D103
    from scalf_opt.api import evaluate
    from scalf_opt.studies import paper_data
    from scalf_opt.viz.report import evaluate_report

    check_output_dir(args.out)
    robot = load_robot(args)
    gait = load_gait(args, robot)
    result = evaluate(robot, gait, accounting=args.accounting, command=args.argv)
    comparison = None
    if paper_data.is_paper_setup(robot, gait) and args.accounting == "paper":
        comparison = ("paper (Table 6)", paper_data.REFERENCE_AVERAGE_POWER_W)
    if args.out is not None:
        written = result.write(args.out)
    args.console.text(evaluate_report(result.cycle, robot.name, comparison=comparison))
    args.console.json(result.to_dict())
    if args.out is not None:
        args.console.text("wrote " + " and ".join(str(p) for p in written))
    return 0
