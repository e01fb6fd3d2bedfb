"""``scalf-opt evaluate``: the energy of the cubic-spline reference trajectory."""

from __future__ import annotations

import argparse
from pathlib import Path

from scalf_opt.cli.options import add_gait, add_robot, load_gait, load_robot

NAME = "evaluate"
HELP = "energy of the cubic-spline reference trajectory"


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    add_robot(parser)
    add_gait(parser)
    parser.add_argument("--out", type=Path, help="write summary.json and samples.csv here")


def run(args: argparse.Namespace) -> int:  # noqa: D103
    from scalf_opt.energy.pipeline import EnergyPipeline
    from scalf_opt.files import write_atomic
    from scalf_opt.io.results import cycle_summary, samples_csv_text, to_json
    from scalf_opt.locomotion.swing.registry import make_family
    from scalf_opt.studies import paper_data
    from scalf_opt.viz.report import evaluate_report

    robot = load_robot(args)
    gait = load_gait(args, robot)
    cycle = EnergyPipeline(robot, gait, args.accounting).robot_cycle(make_family("reference"))
    comparison = None
    if paper_data.is_paper_setup(robot, gait) and args.accounting == "paper":
        comparison = ("paper (Table 6)", paper_data.REFERENCE_AVERAGE_POWER_W)
    print(evaluate_report(cycle, robot.name, comparison=comparison))
    if args.out is not None:
        write_atomic(args.out / "summary.json", to_json(cycle_summary(cycle)))
        write_atomic(args.out / "samples.csv", samples_csv_text(cycle))
        print(f"wrote {args.out / 'summary.json'} and {args.out / 'samples.csv'}")
    return 0
