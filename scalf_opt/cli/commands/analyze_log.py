"""``scalf-opt analyze-log``: the energy in a cylinder log, in the layout of the paper's Table 7."""

from __future__ import annotations

import argparse
from pathlib import Path

from scalf_opt.cli.options import add_robot, gait_overrides, load_gait, load_robot

NAME = "analyze-log"
HELP = "mechanical energy per leg and phase from a cylinder log (lengths and forces)"
EXAMPLES = (
    ("scalf-opt analyze-log results/log.csv", "the energy in a cylinder log (paper Table 7)"),
    ("scalf-opt analyze-log log.csv --period 0.5", "a log without a contact column"),
    ("scalf-opt analyze-log log.csv --json", "the energies as JSON"),
)
JSON = True


def add_arguments(parser: argparse.ArgumentParser) -> None:  # noqa: D103
    parser.add_argument("log", type=Path, metavar="FILE", help="the cylinder log (CSV)")
    add_robot(parser)
    parser.add_argument(
        "--period",
        dest="period_s",
        type=float,
        metavar="X",
        help="the log's gait period [s] (default: the median time between its touch-downs, "
        "else the gait file's, else the robot's default trot's)",
    )
    parser.add_argument(
        "--gait",
        type=Path,
        metavar="FILE",
        help="gait file whose period is used when the log has no contact column",
    )


def run(args: argparse.Namespace) -> int:  # noqa: D103
    from scalf_opt.api import analyze_log
    from scalf_opt.logs.report import log_report

    robot = load_robot(args)
    gait = load_gait(args, robot)
    # --period is the log's period; without it, the contacts' and then the gait's
    period = gait.period_s if "period_s" in gait_overrides(args) else None
    result = analyze_log(args.log, robot, gait, period_s=period, command=args.argv)
    args.console.text(log_report(result.analysis).rstrip("\n"))
    args.console.json(result.to_dict())
    return 0
