"""``scalf-opt analyze-log``: the energy in a cylinder log, in the layout of the paper's Table 7."""

from __future__ import annotations

import argparse
from pathlib import Path

from scalf_opt.cli.options import add_gait, add_robot, load_gait, load_robot
from scalf_opt.errors import ConfigError

NAME = "analyze-log"
HELP = "mechanical energy per leg and phase from a cylinder log (lengths and forces)"


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    parser.add_argument("log", type=Path, metavar="FILE.csv", help="the cylinder log")
    add_robot(parser)
    add_gait(parser, accounting=False)
    parser.add_argument(
        "--period",
        type=float,
        metavar="S",
        help="gait period [s] (default: the median time between touch-downs of the contact "
        "column, else the gait's)",
    )
    parser.add_argument("--json", action="store_true", help="print the result as JSON")


def run(args: argparse.Namespace) -> int:  # noqa: D103
    from scalf_opt.energy.pipeline import EnergyPipeline
    from scalf_opt.io.results import to_json
    from scalf_opt.logs.analysis import analyze_log
    from scalf_opt.logs.log_file import read_log
    from scalf_opt.logs.report import log_report

    if args.period is not None and not args.period > 0:
        raise ConfigError(f"--period must be > 0, got {args.period}")
    robot = load_robot(args)
    pipeline = EnergyPipeline(robot, load_gait(args, robot))
    analysis = analyze_log(read_log(args.log), pipeline, args.period)
    print(to_json(analysis.as_dict()) if args.json else log_report(analysis), end="")
    return 0
